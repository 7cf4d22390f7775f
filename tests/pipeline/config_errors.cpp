// Malformed pipelines: every error carries the file and the JSON pointer of the problem;
// several problems are reported together; data-dependent checks (plugin ids, times against
// the IMU data) happen before any task runs.
#include <gtest/gtest.h>

#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"
#include "inline_pipeline.h"
#include "issue_at.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using imuconv::test::TempDir;
using nlohmann::json;

/// A valid pipeline: 0.1 s of inline samples at 100 Hz and one task of each kind.
json Base() {
  const json state = test::UnitSpeedStartState();
  return test::TenthSecondAt100HzRunning({test::Rk4PropagationOverTenthSecond("prop", state),
                                          test::Rk4PreintegrationAt("pre", {0.0, 0.05, 0.1}),
                                          {{"type", "propagate_by_preintegration"},
                                           {"name", "pbp"},
                                           {"measurements", "pre"},
                                           {"start", {{"state", state}}}},
                                          {{"type", "residual"},
                                           {"name", "res"},
                                           {"kind", "gtsam"},
                                           {"measurements", "pre"},
                                           {"index", 0},
                                           {"start", state},
                                           {"end", state}},
                                          {{"type", "bias_update"},
                                           {"name", "bu"},
                                           {"measurements", "pre"},
                                           {"bias", {{"delta_bg", {0.001, 0, 0}}}}},
                                          {{"type", "convert"},
                                           {"name", "cv"},
                                           {"what", "state_covariance"},
                                           {"source", {{"task", "prop"}}},
                                           {"to", "gtsam_navstate"}}});
}

/// The issues of loading and running `doc` (empty if it runs).
std::vector<Issue> Issues(const json& doc) {
  try {
    const Pipeline p = Pipeline::FromJson(doc, test::kMemPipelineFile, IMUCONV_SOURCE_DIR);
    pipeline::Run(p, imuconv::test::Plugins(), RunOptions{});
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), test::kMemPipelineFile);
    // what() is one "FILE: POINTER: MESSAGE" line per issue.
    const std::string w = e.what();
    EXPECT_EQ(w.rfind(std::string(test::kMemPipelineFile) + ": ", 0), 0u) << w;
    return e.issues();
  }
  return {};
}

TEST(PipelineConfig, BaseRuns) { EXPECT_TRUE(Issues(Base()).empty()); }

TEST(PipelineConfig, UnknownKeys) {
  json d = Base();
  d["colour"] = "blue";
  d["tasks"][0]["propagatr"] = "rk4";
  d["tasks"][0]["interval"]["t_mid"] = 0.05;
  d["imu"]["sampels"] = 1;
  const auto is = Issues(d);
  EXPECT_ISSUE(is, "/colour", "unknown key 'colour'");
  EXPECT_ISSUE(is, "/tasks/0/propagatr", "unknown key 'propagatr' (allowed here: 'type', 'name'");
  EXPECT_ISSUE(is, "/tasks/0/interval/t_mid",
               "unknown key 't_mid' (allowed here: 't_start', 't_end')");
  EXPECT_ISSUE(is, "/imu/sampels", "unknown key 'sampels'");
  EXPECT_EQ(is.size(), 4u);  // all reported at once
}

TEST(PipelineConfig, WrongTypes) {
  json d = Base();
  d["tasks"][0]["interval"]["t_end"] = "soon";
  d["gravity"] = {0, 0};
  d["noise"]["gyro_noise_density"] = -1.0;
  d["tasks"][1]["keyframes"] = {0.0, 0.05, 0.05};
  d["tasks"][2]["start"]["state"]["q_wxyz"] = {1, 0, 0, 0.5};
  d["imu"]["samples"][3] = {0.03, 0.1, "x", 0.3, 0.5, 0.1, 9.8};
  d["tasks"][4]["bias"]["delta_bg"] = {0.001, 0, 0, 0};
  const auto is = Issues(d);
  EXPECT_ISSUE(is, "/tasks/0/interval/t_end", "expected a number, found a string");
  EXPECT_ISSUE(is, "/gravity", "expected an array of 3 numbers, found an array of 2");
  EXPECT_ISSUE(is, "/noise/gyro_noise_density", "expected a non-negative number");
  EXPECT_ISSUE(is, "/tasks/1/keyframes/2", "keyframe times must be strictly increasing");
  EXPECT_ISSUE(is, "/tasks/2/start/state/q_wxyz", "expected a unit quaternion");
  EXPECT_ISSUE(is, "/imu/samples/3/2", "expected a number, found a string");
  EXPECT_ISSUE(is, "/tasks/4/bias/delta_bg", "expected an array of 3 numbers, found an array of 4");
}

TEST(PipelineConfig, NoiseIsRequiredOnlyByTasksThatIntegrateSamples) {
  json d = Base();
  d.erase("noise");
  EXPECT_ISSUE(
      Issues(d), "/noise",
      "required key is missing: task 'prop' (/tasks/0, propagate) integrates IMU samples with it");
  // The same pipeline without its propagate and preintegrate tasks (and those that use their
  // results) has no use for the noise: it runs, and its output records none.
  json conversions = {{"tasks",
                       {{{"type", "convert"},
                         {"name", "cv"},
                         {"what", "state_jacobian"},
                         {"from", "left"},
                         {"to", "gtsam_navstate"},
                         {"state", Base()["tasks"][0]["start"]["state"]}}}}};
  EXPECT_TRUE(Issues(conversions).empty());
  const Pipeline p = Pipeline::FromJson(conversions, test::kMemPipelineFile, IMUCONV_SOURCE_DIR);
  const json out = pipeline::Run(p, imuconv::test::Plugins(), RunOptions{});
  EXPECT_FALSE(out.contains("noise"));
  ASSERT_EQ(out["tasks"].size(), 1u);
  EXPECT_EQ(out["tasks"][0]["name"], "cv");
}

TEST(PipelineConfig, MissingRequiredKeys) {
  json d = Base();
  d["tasks"][0].erase("propagator");
  d["noise"].erase("accel_random_walk");
  d["tasks"][1].erase("keyframes");
  d["tasks"][3].erase("kind");
  const auto is = Issues(d);
  EXPECT_ISSUE(is, "/tasks/0/propagator", "required key is missing");
  EXPECT_ISSUE(is, "/noise/accel_random_walk", "required key is missing");
  EXPECT_ISSUE(is, "/tasks/1/interval",
               "required key is missing (give \"interval\" or \"keyframes\")");
  EXPECT_ISSUE(is, "/tasks/3/kind", "required key is missing");
  json e = Base();
  e.erase("tasks");
  EXPECT_ISSUE(Issues(e), "/tasks", "required key is missing");
}

TEST(PipelineConfig, BadIdsAreCheckedAgainstTheRegistry) {
  json d = Base();
  d["tasks"][0]["state_convention"] = "lefty";
  d["tasks"][0]["propagator"] = "manifold";  // a preintegrator, not a propagator
  d["tasks"][1]["conventions"] = {"gtsam_manifold", "gtsam_manfold"};
  d["tasks"][4]["first_order_charts"] = {"gtsam_navstate"};  // a state convention
  d["tasks"][3]["kind"] = "vins_fussion";  // gtsam, forster or a residual plugin's id
  const auto is = Issues(d);
  EXPECT_ISSUE(is, "/tasks/3/kind",
               "unknown residual kind 'vins_fussion' (did you mean 'vins_fusion'?); known: gtsam, "
               "forster, ");
  EXPECT_ISSUE(is, "/tasks/3/kind", "basalt");
  EXPECT_ISSUE(is, "/tasks/0/state_convention",
               "unknown state convention 'lefty' (did you mean 'left'?); known: ");
  EXPECT_ISSUE(is, "/tasks/0/state_convention", "gtsam_navstate");
  EXPECT_ISSUE(is, "/tasks/0/propagator", "unknown propagator 'manifold'");
  EXPECT_ISSUE(is, "/tasks/0/propagator", "('manifold' is a preintegrator)");
  EXPECT_ISSUE(is, "/tasks/1/conventions/1",
               "unknown increment (preintegration) convention 'gtsam_manfold'");
  EXPECT_ISSUE(is, "/tasks/4/first_order_charts/0", "('gtsam_navstate' is a state_convention)");
  EXPECT_EQ(is.size(), 5u);
}

TEST(PipelineConfig, CovarianceChartMustMatchItsBlocks) {
  json d = Base();
  json diag = json::array();
  for (int i = 0; i < 15; ++i) diag.push_back(1e-4);
  d["tasks"][0]["start"]["cov"] = {{"convention", "gtsam_navstate"},
                                   {"blocks", {"p", "theta", "v", "bg", "ba"}},
                                   {"diagonal", diag}};
  EXPECT_ISSUE(Issues(d), "/tasks/0/start/cov/blocks",
               "blocks [p, theta, v, bg, ba] do not match the block order of 'gtsam_navstate': "
               "[theta, p, v, ba, bg]");
}

TEST(PipelineConfig, IntervalsOutsideTheData) {
  json d = Base();
  d["tasks"][0]["interval"]["t_end"] = 0.5;
  d["tasks"][1]["keyframes"] = {-0.01, 0.05, 0.1};
  const auto is = Issues(d);
  EXPECT_ISSUE(is, "/tasks/0/interval/t_end", "t = 0.5 s is after the last IMU sample (t = 0.1 s");
  EXPECT_ISSUE(is, "/tasks/1/keyframes/0", "t = -0.01 s is before the first IMU sample (t = 0 s");
  json g = Base();
  g["tasks"][1]["keyframes"] = {{"start", 0.0}, {"end", 0.2}, {"step", 0.05}};
  EXPECT_ISSUE(Issues(g), "/tasks/1/keyframes/end", "t = 0.15 s is after the last IMU sample");
}

TEST(PipelineConfig, ReferencesBetweenTasks) {
  json d = Base();
  d["tasks"][2]["measurements"] = "later";
  d["tasks"][3]["measurements"] = "prop";
  d["tasks"][4]["name"] = "pre";
  d["tasks"][5]["source"]["task"] = "pre";  // a preintegrate task for a state conversion
  const auto is = Issues(d);
  EXPECT_ISSUE(is, "/tasks/2/measurements",
               "no earlier preintegrate task named 'later' (earlier ones: 'pre')");
  EXPECT_ISSUE(is, "/tasks/3/measurements",
               "task 'prop' is a propagate task; measurements come from a preintegrate task");
  EXPECT_ISSUE(is, "/tasks/4/name", "duplicate task name 'pre'");
  json e = Base();
  e["tasks"][5]["source"]["task"] = "pre";
  EXPECT_ISSUE(Issues(e), "/tasks/5/source/task",
               "task 'pre' is a preintegrate task; a state_covariance conversion takes");
}

TEST(PipelineConfig, GroundTruthAndImuAreNeededWhereUsed) {
  json d = Base();
  d["tasks"][0]["start"]["state"] = "ground_truth";
  d["tasks"][1]["bias"] = "ground_truth";
  d["tasks"][2]["start"]["state"] = "the truth";
  const auto is = Issues(d);
  EXPECT_ISSUE(is, "/tasks/0/start/state",
               "\"ground_truth\" needs a top-level /ground_truth source");
  EXPECT_ISSUE(is, "/tasks/1/bias", "\"ground_truth\" needs a top-level /ground_truth source");
  EXPECT_ISSUE(is, "/tasks/2/start/state", "found the string 'the truth'");
  json e = Base();
  e.erase("imu");
  EXPECT_ISSUE(Issues(e), "/tasks/0/type",
               "a propagate task needs IMU samples: add a top-level /imu source");
}

TEST(PipelineConfig, UnknownTaskTypeAndEnums) {
  json d = Base();
  d["tasks"][0]["type"] = "integrate";
  d["imu"]["format"] = "inline";
  d["imu"]["time_unit"] = "h";
  const auto is = Issues(d);
  EXPECT_ISSUE(is, "/tasks/0/type",
               "unknown value 'integrate'; expected one of the task types 'propagate'");
  EXPECT_ISSUE(is, "/imu/time_unit", "unknown value 'h'; expected one of 's', 'ms', 'us', 'ns'");
}

TEST(PipelineConfig, DataSourceErrorsNameTheirFiles) {
  // The IMU file is missing: a ReadError naming the file (resolved against the pipeline's
  // directory).
  TempDir tmp;
  json d = Base();
  d["imu"] = {{"format", "euroc"}, {"path", "nowhere/imu.csv"}};
  const Pipeline p = Pipeline::FromJson(d, test::kMemPipelineFile, tmp.path());
  const std::string msg = imuconv::test::MessageOf<ReadError>(
      [&] { pipeline::Run(p, imuconv::test::Plugins(), RunOptions{}); });
  EXPECT_EQ(msg, tmp.file("nowhere/imu.csv") + ": cannot open the file for reading");
}

TEST(PipelineConfig, SyntaxErrorsNameFileLineAndColumn) {
  TempDir tmp;
  const std::string f = tmp.write("p.json", "{\n  \"noise\": {,\n}\n");
  try {
    Pipeline::Load(f);
    FAIL();
  } catch (const ConfigError& e) {
    const std::string w = e.what();
    EXPECT_EQ(w.rfind(f + ": (document): not valid JSON: parse error at line 2, column 13", 0), 0u)
        << w;
  }
  EXPECT_EQ(imuconv::test::MessageOf<ReadError>([&] { Pipeline::Load(tmp.file("absent.json")); }),
            tmp.file("absent.json") + ": cannot open the file for reading");
  // Not an object at all.
  const std::string g = tmp.write("q.json", "[1, 2]");
  EXPECT_EQ(imuconv::test::MessageOf<ConfigError>([&] { Pipeline::Load(g); }),
            g + ": (document): expected an object, found an array");
}

TEST(PipelineConfig, MeasurementFileErrorsPointIntoThatFile) {
  TempDir tmp;
  json m = {{"measurements",
             {{{"dt", 0.1},
               {"bias_estimate", {{"bg", {0, 0, 0}}, {"ba", {0, 0, 0}}}},
               {"delta", {{"q_wxyz", {1, 0, 0, 0}}, {"dp", {0, 0, 0}}}},
               {"J_bias", {{"convention", "gtsam_manifold_jacobian"}, {"matrix", json::array()}}},
               {"cov", {{"convention", "gtsam_manifld"}, {"matrix", json::array()}}}}}}};
  const std::string f = tmp.write("m.json", m.dump());
  json d = Base();
  d["tasks"][2]["measurements"] = {{"file", "m.json"}};
  const Pipeline p = Pipeline::FromJson(d, test::kMemPipelineFile, tmp.path());
  try {
    pipeline::Run(p, imuconv::test::Plugins(), RunOptions{});
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), f);
    EXPECT_ISSUE(e.issues(), "/measurements/0/delta/dv", "required key is missing");
    EXPECT_ISSUE(e.issues(), "/measurements/0/cov/convention",
                 "unknown increment (preintegration) convention 'gtsam_manifld'");
    EXPECT_ISSUE(e.issues(), "/measurements/0/cov/matrix", "expected a 15x15 matrix");
    EXPECT_ISSUE(e.issues(), "/measurements/0/J_bias/matrix", "expected a 9x6 matrix");
  }
}

TEST(PipelineConfig, RuntimeFailuresNameTheTask) {
  json d = Base();
  d["tasks"][5]["source"]["index"] = 3;  // prop has one result
  const Pipeline p = Pipeline::FromJson(d, test::kMemPipelineFile, IMUCONV_SOURCE_DIR);
  const std::string msg = imuconv::test::MessageOf<Error>(
      [&] { pipeline::Run(p, imuconv::test::Plugins(), RunOptions{}); });
  EXPECT_EQ(msg,
            std::string(test::kMemPipelineFile) +
                ": /tasks/5/source/index: task 'prop' has 1 result(s); index 3 is out of range");
  // A start covariance of 1e308 overflows in propagation: the task fails instead of writing null.
  json big = Base();
  json sigma = json::array();
  for (int i = 0; i < 15; ++i) sigma.push_back(1e154);
  big["tasks"][0]["start"]["cov"] = {{"sigma", sigma}};
  const Pipeline q = Pipeline::FromJson(big, test::kMemPipelineFile, IMUCONV_SOURCE_DIR);
  const std::string m2 = imuconv::test::MessageOf<Error>(
      [&] { pipeline::Run(q, imuconv::test::Plugins(), RunOptions{}); });
  EXPECT_NE(
      m2.find(
          std::string(test::kMemPipelineFile) +
          ": /tasks/0 (task 'prop'): produced a non-finite number (output /tasks/0/cov/matrix/"),
      std::string::npos)
      << m2;
}

}  // namespace
