// Memory and time bounded by the work asked (observed through RunOptions::Stats and the
// parsed spec, never by measuring memory or time):
//   - a task's per-interval results are kept only when a later task names it; otherwise
//     they are written and dropped (a 300-byte pipeline with a tiny keyframe step grew past
//     5 GB keeping them);
//   - results that must be kept are estimated before any task runs and refused beyond a
//     limit, naming the task and the numbers;
//   - generated keyframes {start, end, step} store nothing per keyframe;
//   - 100 000 tasks that name earlier ones validate (the name lookups were linear scans).
#include <gtest/gtest.h>

#include <sstream>

#include "../../apps/pipeline/src/spec/pipeline_spec.h"
#include "../../apps/pipeline/src/tasks/task.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"
#include "inline_pipeline.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using nlohmann::json;

const char* kBoundedFile = "mem/bounded.json";

json Doc(const json& tasks) {
  const json samples = test::ConstantSamples(100, 0.01, {0.01, -0.02, 0.03, 0.1, 0.2, 9.8});
  return {{"noise", test::TacticalNoiseDensities()},
          {"imu", {{"format", "inline"}, {"samples", samples}}},
          {"omit", {"Phi", "cov", "J_bias", "R", "reference"}},
          // Keyframes of 1 ms over 100 Hz samples are the point here (many cheap intervals).
          {"allow_empty_intervals", true},
          {"tasks", tasks}};
}

json MovingState() { return {{"p", {0, 0, 0}}, {"q_wxyz", {1, 0, 0, 0}}, {"v", {1, 0, 0}}}; }

/// 1000 keyframe intervals of 1 ms over the second of samples.
json Keyframes() {
  return {{"type", "preintegrate"},
          {"name", "kf"},
          {"method", {{"propagator", "euler"}}},
          {"keyframes", {{"start", 0.0}, {"end", 1.0}, {"step", 0.001}}}};
}
json Predict(bool chain) {
  return {{"type", "propagate_by_preintegration"},
          {"name", "pred"},
          {"measurements", "kf"},
          {"start", {{"state", MovingState()}}},
          {"chain", chain}};
}

RunOptions::Stats RunStats(const json& doc, RunOptions ro = {}) {
  RunOptions::Stats stats;
  ro.stats = &stats;
  const Pipeline p = Pipeline::FromJson(doc, kBoundedFile, IMUCONV_SOURCE_DIR);
  std::size_t bytes = 0;
  RunToText(p, imuconv::test::Plugins(), ro, [&](std::string_view s) { bytes += s.size(); });
  EXPECT_GT(bytes, 0u);
  return stats;
}

TEST(Streaming, IntervalsNoLaterTaskNamesAreNotKept) {
  const RunOptions::Stats alone = RunStats(Doc(json::array({Keyframes()})));
  EXPECT_EQ(alone.records, 1000u);
  EXPECT_EQ(alone.kept_records, 0u);  // was 1000 records of ~2.6 KB
  EXPECT_EQ(alone.kept_bytes, 0u);
  // Named by a later task: kept (1000 measurements), and that task's own steps, named by
  // nothing, are not; chained or not, in parallel or not.
  for (const bool chain : {true, false})
    for (const unsigned threads : {1u, 3u}) {
      SCOPED_TRACE(std::string(chain ? "chained" : "independent") + ", threads " +
                   std::to_string(threads));
      RunOptions ro;
      ro.threads = threads;
      const RunOptions::Stats used = RunStats(Doc(json::array({Keyframes(), Predict(chain)})), ro);
      EXPECT_EQ(used.records, 2000u);
      EXPECT_EQ(used.kept_records, 1000u);
      EXPECT_GT(used.kept_bytes, 1000u * 2000u);  // a measurement holds a 15x15 and a 9x6 matrix
    }
}

TEST(Streaming, TheOutputIsTheSameWhetherResultsAreKeptOrNot) {
  // The preintegrate task's text is the same when a later task keeps its results.
  const auto text = [](const json& doc) {
    const Pipeline p = Pipeline::FromJson(doc, kBoundedFile, IMUCONV_SOURCE_DIR);
    std::string t;
    RunToText(p, imuconv::test::Plugins(), RunOptions{}, [&](std::string_view s) { t.append(s); });
    return json::parse(t);
  };
  const json alone = text(Doc(json::array({Keyframes()})));
  const json used = text(Doc(json::array({Keyframes(), Predict(false)})));
  EXPECT_EQ(alone["tasks"][0], used["tasks"][0]);
}

TEST(Streaming, KeptResultsBeyondTheLimitAreRefusedBeforeAnyTaskRuns) {
  RunOptions ro;
  ro.max_kept_bytes = 100000;  // ~40 measurements
  const Pipeline p = Pipeline::FromJson(Doc(json::array({Keyframes(), Predict(false)})),
                                        kBoundedFile, IMUCONV_SOURCE_DIR);
  std::size_t bytes = 0;
  try {
    RunToText(p, imuconv::test::Plugins(), ro, [&](std::string_view s) { bytes += s.size(); });
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    ASSERT_EQ(e.issues().size(), 1u);
    EXPECT_EQ(e.issues()[0].pointer, "/tasks/0");
    const std::string& m = e.issues()[0].message;
    EXPECT_NE(m.find("task 'kf' has 1000 measurement(s), and a later task uses them "
                     "(/tasks/1/measurements), so they are "
                     "kept in memory: 1000 x "),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("over the limit of 97.7 KiB"), std::string::npos) << m;
  }
  EXPECT_EQ(bytes, 0u);  // nothing was written
  // Not named by a later task, the same intervals are streamed whatever the limit.
  EXPECT_EQ(RunStats(Doc(json::array({Keyframes()})), ro).records, 1000u);
}

TEST(Keyframes, GeneratedKeyframesStoreNothingPerKeyframe) {
  // 1e7 keyframes (the most one task may ask for): the spec holds three numbers.
  json doc = Doc(json::array({Keyframes()}));
  doc["tasks"][0]["keyframes"]["step"] = 1e-7;
  const Pipeline p = Pipeline::FromJson(doc, kBoundedFile, IMUCONV_SOURCE_DIR);
  ASSERT_NE(p.spec().tasks[0]->intervals(), nullptr);
  const IntervalsSpec& iv = *p.spec().tasks[0]->intervals();
  EXPECT_EQ(iv.form, IntervalsSpec::Form::Generated);
  EXPECT_TRUE(iv.times.empty());
  EXPECT_EQ(iv.size(), 10000001u);
  EXPECT_EQ(iv.time(0), 0.0);
  EXPECT_EQ(iv.time(5000000), 0.5);
  EXPECT_EQ(iv.back(), 1.0);
  EXPECT_EQ(iv.pointer_of(0), "/tasks/0/keyframes/start");
  EXPECT_EQ(iv.pointer_of(10000000), "/tasks/0/keyframes/end");
  doc["tasks"][0]["keyframes"]["step"] = 0.9e-7;
  EXPECT_NE(imuconv::test::MessageOf<ConfigError>([&] {
              Pipeline::FromJson(doc, kBoundedFile, IMUCONV_SOURCE_DIR);
            }).find("/tasks/0/keyframes/step: step gives more than 1e7 keyframes"),
            std::string::npos);
}

TEST(Validation, OneHundredThousandTasksThatNameEarlierOnes) {
  // Every task after the first two names an earlier one (measurements, convert source):
  // looked up by name once each. Not timed here (speed is not tested); the lookups are hash
  // maps, and the report gives the measured time.
  json tasks = json::array();
  tasks.push_back({{"type", "preintegrate"},
                   {"name", "pre"},
                   {"method", {{"propagator", "euler"}}},
                   {"keyframes", {0.0, 0.5, 1.0}}});
  tasks.push_back({{"type", "propagate"},
                   {"name", "prop"},
                   {"propagator", "euler"},
                   {"start", {{"state", MovingState()}}},
                   {"interval", {{"t_start", 0.0}, {"t_end", 1.0}}}});
  for (int i = 2; i < 100000; ++i) {
    const std::string name = "t" + std::to_string(i);
    if (i % 3 == 0)
      tasks.push_back({{"type", "residual"},
                       {"name", name},
                       {"kind", "gtsam"},
                       {"measurements", "pre"},
                       {"index", 0},
                       {"start", MovingState()},
                       {"end", MovingState()}});
    else if (i % 3 == 1)
      tasks.push_back({{"type", "convert"},
                       {"name", name},
                       {"what", "state_covariance"},
                       {"source", {{"task", "prop"}}},
                       {"to", "gtsam_navstate"}});
    else
      tasks.push_back({{"type", "bias_update"},
                       {"name", name},
                       {"measurements", "pre"},
                       {"reintegrate", false},
                       {"bias", {{"delta_bg", {0.001, 0, 0}}}}});
  }
  const Pipeline p = Pipeline::FromJson(Doc(tasks), kBoundedFile, IMUCONV_SOURCE_DIR);
  EXPECT_EQ(p.spec().tasks.size(), 100000u);
  // The run-time checks (plugin ids, times, kept memory) without running the tasks.
  RunOptions ro;
  ro.check_only = true;
  std::size_t bytes = 0;
  RunToText(p, imuconv::test::Plugins(), ro, [&](std::string_view s) { bytes += s.size(); });
  EXPECT_EQ(bytes, 0u);
  // And one bad reference among them is still found, with its pointer.
  json bad = Doc(tasks);
  bad["tasks"][99999]["measurements"] = "nowhere";
  const std::string m = imuconv::test::MessageOf<ConfigError>(
      [&] { Pipeline::FromJson(bad, kBoundedFile, IMUCONV_SOURCE_DIR); });
  EXPECT_NE(m.find("/tasks/99999/measurements: no earlier preintegrate task named 'nowhere' "
                   "(earlier ones: 'pre')"),
            std::string::npos)
      << m;
}

}  // namespace
