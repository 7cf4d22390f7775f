// Inputs that used to give a wrong answer in silence are refused, each with the file, the
// JSON pointer and what is wrong: covariances that are not covariances (an indefinite start
// covariance was propagated into a variance of -0.998 and written out), quaternions that are
// not unit, two statements of one value that disagree, IMU gaps; and keyframes
// {start, end, step} keep the remainder of the range as a last, shorter interval.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "../../apps/pipeline/src/forms/input_checks.h"
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

const char* kValidationFile = "mem/validation.json";

json Noise() { return test::TacticalNoiseDensities(); }
json RestState() { return {{"p", {0, 0, 0}}, {"q_wxyz", {1, 0, 0, 0}}, {"v", {0, 0, 0}}}; }

/// Inline samples at rest, 100 Hz from 0 to `seconds`.
json Samples(double seconds) {
  json s = json::array();
  const int n = static_cast<int>(std::lround(seconds * 100));
  for (int k = 0; k <= n; ++k) s.push_back({0.01 * k, 0.0, 0.0, 0.0, 0.0, 0.0, 9.81});
  return s;
}

/// A pipeline of `tasks` (one task object, or an array) over `seconds` of samples.
json Pipeline1(const json& tasks, double seconds = 1.0) {
  // {task} in braces is the task itself to nlohmann::json, not an array of one: wrap it.
  const json list = tasks.is_array() ? tasks : json::array({tasks});
  return {{"noise", Noise()},
          {"imu", {{"format", "inline"}, {"samples", Samples(seconds)}}},
          {"tasks", list}};
}

/// 15x15 with `var` on the diagonal.
json Diagonal(double var) {
  json m = json::array();
  for (int i = 0; i < 15; ++i) {
    json r = json::array();
    for (int k = 0; k < 15; ++k) r.push_back(i == k ? var : 0.0);
    m.push_back(r);
  }
  return m;
}

/// The start covariance of the -0.998 report: p_x and v_x with variance 1 and covariance c
/// (left chart: p is block 0, v block 2), the rest 1e-6. |c| > 1 is not a covariance.
json PxVxCov(double c) {
  json m = Diagonal(1e-6);
  m[0][0] = 1.0;
  m[6][6] = 1.0;
  m[0][6] = c;
  m[6][0] = c;
  return m;
}

json Propagate(const json& cov) {
  return {{"type", "propagate"},
          {"name", "prop"},
          {"propagator", "rk4"},
          {"start", {{"state", RestState()}, {"cov", cov}}},
          {"interval", {{"t_start", 0.0}, {"t_end", 1.0}}}};
}

struct Outcome {
  json out;
  std::vector<Issue> issues;
  std::string file;  // of the ConfigError
  std::string summary;
};

Outcome RunDoc(const json& doc, const std::string& base = IMUCONV_SOURCE_DIR) {
  Outcome o;
  try {
    const Pipeline p = Pipeline::FromJson(doc, kValidationFile, base);
    std::ostringstream s;
    RunOptions ro;
    ro.summary = &s;
    o.out = pipeline::Run(p, imuconv::test::Plugins(), ro);
    o.summary = s.str();
  } catch (const ConfigError& e) {
    o.issues = e.issues();
    o.file = e.file();
  }
  return o;
}

// ---- covariances ----------------------------------------------------------------------

TEST(Covariances, TheIndefiniteStartCovarianceOfTheReportIsRefused) {
  // Correlation -1.499 between p_x and v_x: propagated over 1 s at rest, var(p_x) becomes
  // 1 - 2 * 1.499 + 1 = -0.998, which is what was written out before this check.
  const Outcome bad = RunDoc(Pipeline1({Propagate(PxVxCov(-1.499))}));
  ASSERT_FALSE(bad.issues.empty()) << bad.out.dump().substr(0, 300);
  EXPECT_EQ(bad.file, kValidationFile);
  const std::string m = test::IssueAt(bad.issues, "/tasks/0/start/cov");
  EXPECT_NE(
      m.find("not a valid covariance: not positive semi-definite: smallest eigenvalue -0.499"),
      std::string::npos)
      << m;
  EXPECT_NE(m.find("nothing is repaired"), std::string::npos) << m;
  // A correlation of -0.999 is a covariance: it runs, and every variance written is >= 0.
  const Outcome ok = RunDoc(Pipeline1({Propagate(PxVxCov(-0.999))}));
  ASSERT_TRUE(ok.issues.empty()) << ok.issues[0].pointer << ": " << ok.issues[0].message;
  const auto cov = imuconv::test::JsonMatrix(ok.out["tasks"][0]["cov"]["matrix"]);
  ASSERT_EQ(cov.rows(), 15);
  EXPECT_GE(cov.diagonal().minCoeff(), 0.0);
  EXPECT_NEAR(cov(0, 0), 1.0 - 2 * 0.999 + 1.0, 1e-3);  // 0.002 plus the noise over 1 s (< 1e-4)
}

TEST(Covariances, EveryFormAndEveryPlaceIsChecked) {
  json neg = json::array();
  for (int i = 0; i < 15; ++i) neg.push_back(i == 6 ? -1.0 : 1e-4);
  json asym = Diagonal(1.0);
  asym[0][1] = 0.5;  // (1, 0) stays 0
  json tasks = {
      Propagate({{"diagonal", neg}}),
      test::Rk4PreintegrationAt("pre", {0.0, 0.5, 1.0}),
      {{"type", "propagate_by_preintegration"},
       {"name", "pbp"},
       {"measurements", "pre"},
       {"start",
        {{"state", RestState()}, {"cov", {{"convention", "gtsam_navstate"}, {"matrix", asym}}}}}},
      {{"type", "convert"},
       {"name", "cv"},
       {"what", "state_covariance"},
       {"from", "left"},
       {"to", "gtsam_navstate"},
       {"state", RestState()},
       {"matrix", PxVxCov(2.0)}},
      // A transition matrix is not a covariance: not symmetric, and accepted.
      {{"type", "convert"},
       {"name", "tr"},
       {"what", "state_transition"},
       {"from", "left"},
       {"to", "gtsam_navstate"},
       {"state", RestState()},
       {"state_end", RestState()},
       {"matrix", asym}},
      {{"type", "convert"},
       {"name", "ic"},
       {"what", "increment_covariance"},
       {"from", "preint_reference"},
       {"to", "gtsam_manifold"},
       {"increment", {{"q_wxyz", {1, 0, 0, 0}}, {"dp", {0, 0, 0}}, {"dv", {0, 0, 0}}}},
       {"matrix", {{"diagonal", neg}}}}};
  const Outcome o = RunDoc(Pipeline1(tasks));
  EXPECT_ISSUE(o.issues, "/tasks/0/start/cov", "diagonal entry (6, 6) = -1 is negative");
  EXPECT_ISSUE(o.issues, "/tasks/0/start/cov", "smallest eigenvalue of (C + C^T)/2: -1");
  EXPECT_ISSUE(o.issues, "/tasks/2/start/cov",
               "not symmetric: entries (0, 1) = 0.5 and (1, 0) = 0");
  EXPECT_ISSUE(o.issues, "/tasks/3/matrix", "not positive semi-definite: smallest eigenvalue -1");
  EXPECT_ISSUE(o.issues, "/tasks/5/matrix", "diagonal entry (6, 6) = -1 is negative");
  EXPECT_EQ(o.issues.size(), 4u);  // not /tasks/4/matrix
}

json Measurement() {
  json jb = json::array();
  for (int i = 0; i < 9; ++i) jb.push_back(std::vector<double>(6, 0.0));
  return {{"t_start", 0.0},
          {"t_end", 0.5},
          {"dt", 0.5},
          {"bias_estimate", {{"bg", {0, 0, 0}}, {"ba", {0, 0, 0}}}},
          {"delta", {{"q_wxyz", {1, 0, 0, 0}}, {"dp", {0, 0, 0}}, {"dv", {0, 0, 0}}}},
          {"J_bias", {{"convention", "preint_reference"}, {"matrix", jb}}},
          {"cov", {{"convention", "preint_reference"}, {"matrix", Diagonal(1e-4)}}}};
}

/// Runs a propagate_by_preintegration task over a measurements file holding `ms`; the
/// issues of the file (or of the pipeline).
Outcome RunFile(const json& ms, const TempDir& tmp) {
  tmp.write("m.json", json({{"measurements", ms.is_array() ? ms : json::array({ms})}}).dump());
  const json doc = {{"noise", Noise()},
                    {"tasks",
                     {{{"type", "propagate_by_preintegration"},
                       {"name", "pbp"},
                       {"measurements", {{"file", "m.json"}}},
                       {"start", {{"state", RestState()}}}}}}};
  return RunDoc(doc, tmp.path());
}

TEST(Covariances, MeasurementFilesAreCheckedWhereTheyAre) {
  TempDir tmp;
  json m = Measurement();
  m["cov"]["matrix"] = PxVxCov(-3.0);
  const Outcome o = RunFile({Measurement(), m}, tmp);
  EXPECT_EQ(o.file, tmp.file("m.json"));
  EXPECT_ISSUE(o.issues, "/measurements/1/cov/matrix",
               "not positive semi-definite: smallest eigenvalue -2");
  EXPECT_EQ(o.issues.size(), 1u);
  EXPECT_TRUE(RunFile({Measurement()}, tmp).issues.empty());
}

TEST(Covariances, ComputedOutputsWithANegativeVarianceAreNotWritten) {
  // From valid inputs a negative variance is a defect (of imuconv or a plugin): reported,
  // naming the output pointer. Round-off below 1e-9 of the largest variance is not.
  Mat15 C = Mat15::Identity();
  C(4, 4) = -1e-3;
  const std::string m =
      imuconv::test::MessageOf([&] { CheckOutputCovariance(C, "/tasks/2/steps/7/cov/matrix"); });
  EXPECT_NE(m.find("negative variance, entry (4, 4) = -0.001 (output /tasks/2/steps/7/cov/matrix"),
            std::string::npos)
      << m;
  EXPECT_NE(m.find("please report it"), std::string::npos) << m;
  C(4, 4) = -1e-12;
  EXPECT_EQ(imuconv::test::MessageOf([&] { CheckOutputCovariance(C, "/x"); }), "");
}

// ---- quaternions and rotations ----------------------------------------------------------

TEST(Quaternions, RunsRuleHoldsForStatesIncrementsAndFiles) {
  json tasks = {
      {{"type", "propagate"},
       {"name", "zero"},
       {"propagator", "rk4"},
       {"start", {{"state", {{"p", {0, 0, 0}}, {"q_wxyz", {0, 0, 0, 0}}, {"v", {0, 0, 0}}}}}},
       {"interval", {{"t_start", 0.0}, {"t_end", 1.0}}}},
      {{"type", "propagate"},
       {"name", "two"},
       {"propagator", "rk4"},
       {"start", {{"state", {{"p", {0, 0, 0}}, {"q_wxyz", {2, 0, 0, 0}}, {"v", {0, 0, 0}}}}}},
       {"interval", {{"t_start", 0.0}, {"t_end", 1.0}}}},
      // Within 1e-6 of unit norm: accepted (and normalised).
      {{"type", "propagate"},
       {"name", "near"},
       {"propagator", "rk4"},
       {"start",
        {{"state", {{"p", {0, 0, 0}}, {"q_wxyz", {1.0000005, 0, 0, 0}}, {"v", {0, 0, 0}}}}}},
       {"interval", {{"t_start", 0.0}, {"t_end", 1.0}}}},
      {{"type", "convert"},
       {"name", "inc"},
       {"what", "increment_jacobian"},
       {"from", "preint_reference"},
       {"to", "gtsam_manifold"},
       {"increment", {{"q_wxyz", {0.7, 0.7, 0, 0}}, {"dp", {0, 0, 0}}, {"dv", {0, 0, 0}}}}},
      {{"type", "residual"},
       {"name", "res"},
       {"kind", "gtsam"},
       {"measurements", {{"file", "m.json"}}},
       {"start", RestState()},
       {"end", {{"p", {0, 0, 0}}, {"q_wxyz", {1, 1, 0, 0}}, {"v", {0, 0, 0}}}}}};
  TempDir tmp;
  json m = Measurement();
  m["delta"]["q_wxyz"] = {0.5, 0, 0, 0};
  tmp.write("m.json", json({{"measurements", {m}}}).dump());
  try {
    Pipeline::FromJson(Pipeline1(tasks), kValidationFile, tmp.path());
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_ISSUE(
        e.issues(), "/tasks/0/start/state/q_wxyz",
        "expected a unit quaternion [w, x, y, z] (norm within 1e-6 of 1), found one of norm 0");
    EXPECT_ISSUE(e.issues(), "/tasks/1/start/state/q_wxyz", "found one of norm 2");
    EXPECT_ISSUE(e.issues(), "/tasks/3/increment/q_wxyz", "found one of norm 0.9899494937");
    EXPECT_ISSUE(e.issues(), "/tasks/4/end/q_wxyz", "found one of norm 1.414213562");
    EXPECT_EQ(e.issues().size(), 4u);  // not the near-unit one
  }
  // The measurement file's quaternion, with the same rule.
  const Outcome f = RunFile({m}, tmp);
  EXPECT_ISSUE(f.issues, "/measurements/0/delta/q_wxyz", "found one of norm 0.5");
}

TEST(Quaternions, SeveralStatementsOfARotationMustAgree) {
  TempDir tmp;
  const double c = std::cos(0.05), s = std::sin(0.05);  // 0.1 rad about z
  json agree = Measurement();
  agree["delta"] = {
      {"q_wxyz", {c, 0, 0, s}},
      {"R", {{std::cos(0.1), -std::sin(0.1), 0}, {std::sin(0.1), std::cos(0.1), 0}, {0, 0, 1}}},
      {"rotation_angle_deg", 0.1 * 180 / 3.14159265358979323846},
      {"dp", {0, 0, 0}},
      {"dv", {0, 0, 0}}};
  json r_differs = agree;
  r_differs["delta"]["R"] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  json angle_differs = agree;
  angle_differs["delta"]["rotation_angle_deg"] = 6.0;
  json times_differ = Measurement();
  times_differ["t_start_abs_ns"] = 7;  // the pipeline has no time origin here: nothing to compare
  json index_differs = Measurement();
  index_differs["index"] = 7;
  const Outcome o = RunFile({agree, r_differs, angle_differs, times_differ, index_differs}, tmp);
  EXPECT_ISSUE(o.issues, "/measurements/1/delta/R",
               "R and q_wxyz disagree by 5.72958 deg (tolerance 1e-6 deg)");
  EXPECT_ISSUE(o.issues, "/measurements/2/delta/rotation_angle_deg",
               "does not match the rotation's angle 5.72957795");
  EXPECT_ISSUE(o.issues, "/measurements/4/index", "index 7 is not the measurement's position 4");
  EXPECT_EQ(o.issues.size(), 3u);
  // The same increment form in a convert task: both given and agreeing is accepted.
  const json cv = {
      {"type", "convert"},          {"name", "cv"},           {"what", "increment_jacobian"},
      {"from", "preint_reference"}, {"to", "gtsam_manifold"}, {"increment", agree["delta"]}};
  const Outcome ok = RunDoc(Pipeline1({cv}));
  EXPECT_TRUE(ok.issues.empty()) << test::IssueAt(ok.issues, "");
  json bad = cv;
  bad["increment"] = r_differs["delta"];
  EXPECT_ISSUE(RunDoc(Pipeline1({bad})).issues, "/tasks/0/increment/R", "R and q_wxyz disagree");
}

TEST(Measurements, RelativeAndAbsoluteTimesMustAgree) {
  // With a time origin on both sides, t_start and t_start_abs_ns are two statements of one
  // time: neither silently wins.
  TempDir tmp;
  json ms = json::array();
  for (int k = 0; k < 2; ++k) {
    json m = Measurement();
    m["t_start"] = 0.5 * k;
    m["t_end"] = 0.5 * k + 0.5;
    m["t_start_abs_ns"] = 1000000000LL + 500000000LL * k;
    m["t_end_abs_ns"] = 1000000000LL + 500000000LL * (k + 1);
    ms.push_back(m);
  }
  ms[1]["t_end"] = 1.6;  // t_end_abs_ns (and dt) say 1.0 s
  tmp.write("m.json", json({{"time_origin_ns", 1000000000LL}, {"measurements", ms}}).dump());
  json doc = Pipeline1({{{"type", "propagate_by_preintegration"},
                         {"name", "pbp"},
                         {"measurements", {{"file", "m.json"}}},
                         {"start", {{"state", RestState()}}}}});
  doc["imu"]["time_origin"] = "1";  // seconds: the same origin as the file's, 1e9 ns
  const Outcome o = RunDoc(doc, tmp.path());
  EXPECT_ISSUE(o.issues, "/measurements/1/t_end",
               "t_end places the measurement at 1.6 s but t_end_abs_ns at 1 s");
  EXPECT_EQ(o.issues.size(), 1u);
}

// ---- keyframes {start, end, step} -----------------------------------------------------------

json Keyframes(double start, double end, double step) {
  return test::Rk4PreintegrationAt("kf", {{"start", start}, {"end", end}, {"step", step}});
}

std::vector<std::pair<double, double>> Spans(const json& out) {
  std::vector<std::pair<double, double>> v;
  for (const auto& m : out["tasks"][0]["measurements"])
    v.emplace_back(m["t_start"].get<double>(), m["t_end"].get<double>());
  return v;
}

TEST(Keyframes, TheRemainderIsALastShorterIntervalEndingAtEnd) {
  // 1 / 0.3: three whole steps and 0.1 s left over. It used to be dropped in silence.
  const Outcome o = RunDoc(Pipeline1({Keyframes(0.0, 1.0, 0.3)}));
  ASSERT_TRUE(o.issues.empty()) << test::IssueAt(o.issues, "");
  const std::vector<std::pair<double, double>> want = {
      {0.0, 0.3}, {0.3, 0.6}, {0.6, 0.9}, {0.9, 1.0}};
  EXPECT_EQ(Spans(o.out), want);  // exact: keyframes snap to the nanosecond within round-off
  EXPECT_NE(o.summary.find(
                "the last interval, [0.9, 1] s, is the 0.1 s left after 3 whole step(s) of 0.3 s"),
            std::string::npos)
      << o.summary;
}

TEST(Keyframes, RoundOffIsNotARemainder) {
  // 0.3 / 0.1 = 2.9999999999999996 and 1 / 0.1 = 10 in double: whole steps, `end` is the
  // last keyframe, no sliver of an interval and nothing in the summary.
  for (const auto& [end, step, n] :
       {std::tuple<double, double, std::size_t>{0.3, 0.1, 3}, {1.0, 0.1, 10}, {0.7, 0.07, 10}}) {
    SCOPED_TRACE(std::to_string(end) + " / " + std::to_string(step));
    const Outcome o = RunDoc(Pipeline1({Keyframes(0.0, end, step)}));
    ASSERT_TRUE(o.issues.empty()) << test::IssueAt(o.issues, "");
    const auto spans = Spans(o.out);
    ASSERT_EQ(spans.size(), n);
    EXPECT_EQ(spans.back().second, end);
    for (const auto& [a, b] : spans) EXPECT_NEAR(b - a, step, 1e-12);
    EXPECT_EQ(o.summary.find("left after"), std::string::npos) << o.summary;
  }
}

TEST(Keyframes, AStepLongerThanTheRangeIsAnError) {
  const Outcome o = RunDoc(Pipeline1({Keyframes(0.0, 0.5, 0.6)}));
  EXPECT_ISSUE(o.issues, "/tasks/0/keyframes/step", "step is longer than end - start");
}

// ---- IMU timing ------------------------------------------------------------------------------

TEST(InlineSamples, GapsAreErrorsAtTheSampleUnlessAllowed) {
  json doc = Pipeline1({Propagate({{"diagonal", std::vector<double>(15, 1e-4)}})}, 2.0);
  json& s = doc["imu"]["samples"];
  s.erase(s.begin() + 31, s.begin() + 81);  // 0.31 .. 0.80 s missing: a 0.51 s gap before sample 31
  const Outcome o = RunDoc(doc);
  EXPECT_ISSUE(
      o.issues, "/imu/samples/31/0",
      "gap of 0.51 s before this sample (the median period is 0.01 s; limit 10 x median = 0.1 s)");
  EXPECT_ISSUE(o.issues, "/imu/samples/31/0", "\"allow_gaps\": true");
  json allowed = doc;
  allowed["imu"]["allow_gaps"] = true;
  EXPECT_TRUE(RunDoc(allowed).issues.empty());
  json wider = doc;
  wider["imu"]["max_gap_factor"] = 60;
  EXPECT_TRUE(RunDoc(wider).issues.empty());
  json bad = doc;
  bad["imu"]["max_gap_factor"] = 1;
  bad["imu"]["allow_gaps"] = "yes";
  const Outcome b = RunDoc(bad);
  EXPECT_ISSUE(b.issues, "/imu/max_gap_factor", "expected a number > 1");
  EXPECT_ISSUE(b.issues, "/imu/allow_gaps", "expected true or false");
}

TEST(InlineSamples, NanosecondsDeclaredAsSecondsNameTheUnit) {
  json doc = Pipeline1({Keyframes(0.0, 1.0, 0.5)});
  for (auto& row : doc["imu"]["samples"])
    row[0] = static_cast<std::int64_t>(std::llround(row[0].get<double>() * 1e9));
  const Outcome o = RunDoc(doc);
  EXPECT_ISSUE(o.issues, "/imu/samples",
               "the timestamps look like nanoseconds: set time_unit to \"ns\"");
}

TEST(GroundTruth, TimingKeysAreValidated) {
  json doc = Pipeline1({Keyframes(0.0, 1.0, 0.5)});
  doc["ground_truth"] = {
      {"format", "euroc"}, {"path", "gt.csv"}, {"max_gap_factor", 0.5}, {"allow_gaps", 1}};
  const Outcome o = RunDoc(doc);
  EXPECT_ISSUE(o.issues, "/ground_truth/max_gap_factor", "expected a number > 1");
  EXPECT_ISSUE(o.issues, "/ground_truth/allow_gaps", "expected true or false");
}

}  // namespace
