// Issue 22, "no wrong answer in silence", the timing part, through the command line: a chain of
// measurements that does not tile time, IMU stamps in the wrong unit that the rate check alone
// lets through, intervals holding no sample (keyframes finer than the samples), and `imuconv
// check` on imuconv's own measurements whose keyframes lie a rounding off a sample. Each was
// exit 0 with a wrong answer, or a whole command failing, before; each case beyond the issue's
// own examples is marked "hostile". A refused run exits 2 (bad input, nothing written: the one
// exit-code table, apps/exit_codes.h), as its other input errors do.
//
// The data are synthetic (a slow turn and a gentle push, 200 Hz unless said), written by the
// tests; nothing from outside the repository. The examples/ pipeline is the repository's own.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "../pipeline/inline_pipeline.h"
#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"
#include "number_text.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

const json kNoise = NoiseDensities(1.7e-4, 2.0e-3, 1.9e-5, 3.0e-3);

/// `n` samples at `rate` Hz, the time column written as k x stamp_step (the stamps' own
/// unit; the pipeline declares one), header t,wx,wy,wz,ax,ay,az.
std::string ImuCsv(int n, double stamp_step) {
  std::string s = "t,wx,wy,wz,ax,ay,az\n";
  for (int k = 0; k < n; ++k) {
    const double t = k / 200.0;
    s += Num17(k * stamp_step) + ",0.1,-0.2,0.3," + Num17(0.2 * std::sin(t)) + ",0,9.81\n";
  }
  return s;
}

json CsvImu(const std::string& path, const std::string& unit) {
  return {{"format", "csv"},
          {"path", path},
          {"header_rows", 1},
          {"time_unit", unit},
          {"columns", CsvColumnsNamedByChannel("t")}};
}

json Preintegrate(const std::string& name, const json& keyframes) {
  return {{"type", "preintegrate"},
          {"name", name},
          {"method", {{"propagator", "rk4"}}},
          {"conventions", {"gtsam_manifold"}},
          {"keyframes", keyframes}};
}

// ---- 1. chained measurements ----

class Chain : public ::testing::Test {
 protected:
  void SetUp() override {
    csv = tmp.write("imu.csv", ImuCsv(401, 1.0 / 200.0));  // 2 s
    const json p = {{"noise", kNoise},
                    {"imu", CsvImu(csv, "s")},
                    {"tasks",
                     {Preintegrate("a", json::array({0.0, 0.5, 1.0, 1.5})),
                      Preintegrate("b", json::array({0.25, 0.75}))}}};
    const auto r = RunImuconv("run " + ShellQuote(tmp.write("make.json", p.dump())) + " -o " +
                                  ShellQuote(tmp.file("made.json")),
                              tmp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json out = ReadJson(tmp.file("made.json"));
    a = out["tasks"][0]["measurements"];
    b = out["tasks"][1]["measurements"];
    ASSERT_EQ(a.size(), 3u);
    ASSERT_EQ(b.size(), 1u);
  }

  /// `imuconv run` of a chained propagate_by_preintegration over these measurements (their
  /// "index", the position in the task's output, dropped: a file's order is its own).
  CommandResult RunChain(const std::string& tag, json measurements) {
    for (auto& m : measurements) m.erase("index");
    const std::string meas =
        tmp.write(tag + ".meas.json", json{{"measurements", measurements}}.dump());
    const json p = {{"noise", kNoise},
                    {"imu", CsvImu(csv, "s")},
                    {"tasks",
                     {{{"type", "propagate_by_preintegration"},
                       {"name", "chained"},
                       {"measurements", {{"file", meas}}},
                       {"start", {{"state", RestAtOriginWithZeroBiases()}}},
                       {"chain", true}}}}};
    return RunImuconv("run " + ShellQuote(tmp.write(tag + ".json", p.dump())) + " -o " +
                          ShellQuote(tmp.file(tag + ".out.json")),
                      tmp);
  }

  TempDir tmp;
  std::string csv;
  json a, b;
};

TEST_F(Chain, ContiguousMeasurementsChain) {
  const auto r = RunChain("ok", a);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(ReadJson(tmp.file("ok.out.json"))["tasks"][0]["steps"].size(), 3u);
}

TEST_F(Chain, AGapIsRefusedNamingBothIntervals) {
  const auto r = RunChain("gap", json::array({a[0], a[2]}));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "/tasks/0/chain")) << r.err;
  EXPECT_TRUE(Has(
      r.err, "measurement 1 (" + tmp.file("gap.meas.json") + ": /measurements/1, [1 s, 1.5 s])"))
      << r.err;
  EXPECT_TRUE(Has(r.err, "leaves a gap of 0.5 s after measurement 0 (")) << r.err;
  EXPECT_TRUE(Has(r.err, "/measurements/0, [0 s, 0.5 s])")) << r.err;
  EXPECT_FALSE(fs::exists(tmp.file("gap.out.json")));
}

TEST_F(Chain, BackwardsAndRepeatedIntervalsAreRefused) {
  const auto back = RunChain("back", json::array({a[1], a[0]}));
  EXPECT_EQ(back.exit_code, 2) << back.err;
  EXPECT_TRUE(Has(back.err, "runs backwards")) << back.err;
  const auto again = RunChain("again", json::array({a[0], a[1], a[1]}));
  EXPECT_EQ(again.exit_code, 2) << again.err;
  EXPECT_TRUE(Has(again.err, "measurement 2 (")) << again.err;
  EXPECT_TRUE(Has(again.err, "repeats the interval of measurement 1 (")) << again.err;
}

TEST_F(Chain, HostileOverlapByHalfAnIntervalIsRefused) {
  // [0, 0.5] then [0.25, 0.75]: the second quarter would be integrated twice.
  const auto r = RunChain("overlap", json::array({a[0], b[0]}));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "overlaps by 0.25 s")) << r.err;
}

// ---- 2. time units ----

/// A TUM ground truth (seconds) at 100 Hz over [0, 2] s, at rest.
std::string TumGroundTruth(const TempDir& tmp) {
  std::string s;
  for (int k = 0; k <= 200; ++k) s += Num17(k / 100.0) + " 0 0 0 0 0 0 1\n";
  return tmp.write("gt.tum", s);
}

CommandResult RunWithGroundTruth(const TempDir& tmp, const std::string& tag, const std::string& csv,
                                 const std::string& unit, const json& keyframes) {
  const json p = {{"noise", kNoise},
                  {"imu", CsvImu(csv, unit)},
                  {"ground_truth", {{"format", "tum"}, {"path", TumGroundTruth(tmp)}}},
                  {"tasks", {Preintegrate("kf", keyframes)}}};
  return RunImuconv("run " + ShellQuote(tmp.write(tag + ".json", p.dump())) + " -o " +
                        ShellQuote(tmp.file(tag + ".out.json")),
                    tmp);
}

TEST(TimeUnit, MillisecondsDeclaredAsSecondsAreRefusedAgainstTheGroundTruth) {
  // A 1 kHz IMU with millisecond stamps read as seconds is a 1 Hz IMU: inside the plausible
  // 1 Hz..100 kHz, so the rate check alone passes it. The 100 Hz ground truth does not.
  TempDir tmp;
  std::string csv = "t,wx,wy,wz,ax,ay,az\n";
  for (int k = 0; k <= 2000; ++k) csv += std::to_string(k) + ",0.1,-0.2,0.3,0,0,9.81\n";
  const std::string path = tmp.write("ms.csv", csv);
  const auto r = RunWithGroundTruth(tmp, "ms", path, "s", json::array({0.0, 1.0}));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(
      Has(r.err, "the IMU's median period is 1 s (1 Hz) but the ground truth's is 0.01 s (100 Hz)"))
      << r.err;
  EXPECT_TRUE(Has(r.err, "look like ms, not s: set time_unit to \"ms\"")) << r.err;
  EXPECT_FALSE(fs::exists(tmp.file("ms.out.json")));
  // The same stamps declared as what they are run.
  const auto ok = RunWithGroundTruth(tmp, "ms_ok", path, "ms", json::array({0.0, 1.0}));
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

TEST(TimeUnit, HostileMicrosecondsDeclaredAsNanoseconds) {
  // 50 Hz in microseconds read as nanoseconds: 2e-5 s, 50 kHz, inside the plausible range;
  // against the 100 Hz ground truth it is 500x too fast.
  TempDir tmp;
  const std::string path = tmp.write("us.csv", ImuCsv(201, 20000.0));
  const auto r = RunWithGroundTruth(tmp, "us", path, "ns", json::array({0.0, 0.001}));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "/imu/time_unit")) << r.err;
  EXPECT_TRUE(Has(r.err, "look like us, not ns: set time_unit to \"us\"")) << r.err;
}

// ---- 4. intervals holding no sample ----

CommandResult RunKeyframes(const TempDir& tmp, const std::string& tag, const json& keyframes,
                           bool allow = false) {
  json p = {{"noise", kNoise},
            {"imu", CsvImu(tmp.write("imu.csv", ImuCsv(381, 1.0 / 200.0)), "s")},  // 1.9 s
            {"tasks", {Preintegrate("kf", keyframes)}}};
  if (allow) p["allow_empty_intervals"] = true;
  return RunImuconv("run " + ShellQuote(tmp.write(tag + ".json", p.dump())) + " -o " +
                        ShellQuote(tmp.file(tag + ".out.json")),
                    tmp);
}

TEST(EmptyIntervals, KeyframesFinerThanTheSamplesFailBeforeAnyWork) {
  // The case: 2.1e-7 s over 1.9 s of 200 Hz is 9 million intervals (minutes, 8.5 GB
  // of output before). Refused in the check-times stage, naming the step and the period.
  TempDir tmp;
  const auto r = RunKeyframes(tmp, "fine", {{"start", 0.0}, {"end", 1.9}, {"step", 2.1e-7}});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "/tasks/0/keyframes/step")) << r.err;
  EXPECT_TRUE(
      Has(r.err,
          "holds no IMU sample: the keyframe step is 2.1e-07 s, the IMU period 0.005 s (median)"))
      << r.err;
  EXPECT_TRUE(Has(r.err, "\"allow_empty_intervals\": true")) << r.err;
  EXPECT_FALSE(fs::exists(tmp.file("fine.out.json")));
}

TEST(EmptyIntervals, HostileOneSubSampleIntervalAmongGoodOnes) {
  // [0.5, 0.6001] holds samples, [0.6001, 0.6021] none (they are at 0.6 and 0.605).
  TempDir tmp;
  const json kf = json::array({0.5, 0.6001, 0.6021});
  const auto r = RunKeyframes(tmp, "one", kf);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "/tasks/0/keyframes/2")) << r.err;
  EXPECT_TRUE(Has(r.err, "interval 1 [0.6001, 0.6021] s holds no IMU sample: it is 0.002 s"))
      << r.err;
  // Said to be meant, it runs: both intervals, the second by interpolation alone.
  const auto ok = RunKeyframes(tmp, "meant", kf, true);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(ReadJson(tmp.file("meant.out.json"))["tasks"][0]["measurements"].size(), 2u);
}

TEST(EmptyIntervals, HostileRepeatedKnotIsRefused) {
  // Already refused before (keyframes must increase strictly); kept beside the new rule, whose
  // zero-length interval it would otherwise be.
  TempDir tmp;
  const auto r = RunKeyframes(tmp, "repeat", json::array({0.1, 0.2, 0.2, 0.3}));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "/tasks/0/keyframes/2")) << r.err;
}

// ---- 5. imuconv check on imuconv's own measurements ----

TEST(CheckOwnMeasurements, TheShippedEurocExampleChecks) {
  // Keyframes k x 0.1 (0.30000000000000004, ...) lie a rounding off the EuRoC samples; a
  // knot within a nanosecond of a sample is that sample (core window.h, kSameInstant). Before,
  // Basalt's reference refused the 4e-17 s step and the whole command failed (exit 2).
  TempDir tmp;
  const std::string pipeline = SourcePath("examples/euroc_v1_01_keyframes.json");
  const auto run =
      RunImuconv("run " + ShellQuote(pipeline) + " -o " + ShellQuote(tmp.file("out.json")), tmp);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // The measurements file: the kf_rk4 task's measurements, on the run's time origin.
  const json out = ReadJson(tmp.file("out.json"));
  const std::string meas =
      tmp.write("M.json", json{{"time_origin_ns", out["time_origin_ns"]},
                               {"measurements", out["tasks"][0]["measurements"]}}
                              .dump());
  const auto r = RunImuconv(
      "check " + ShellQuote(meas) + " --pipeline " + ShellQuote(pipeline) + " --json", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json report = json::parse(r.out);
  EXPECT_EQ(report["verdict"], "consistent");
  ASSERT_EQ(report["measurements"].size(), 200u);  // 20 s at 10 Hz
  for (const auto& m : report["measurements"]) {
    EXPECT_FALSE(m.contains("not_applicable")) << m["pointer"];
    EXPECT_EQ(m["best"]["scheme"], "rk4") << m["pointer"];  // the task's own propagator
  }
}

TEST(CheckOwnMeasurements, HostileReferenceThatCannotRunIsNotApplicable) {
  // tests/fixtures/override: an `rk4` propagator that refuses every interval, chosen over the
  // built-in one with --allow-plugin-override. The rk4 reference is then not applicable; the
  // other schemes still judge the measurement (made by euler: consistent).
  TempDir tmp;
  const std::string csv = tmp.write("imu.csv", ImuCsv(201, 1.0 / 200.0));
  json pre = Preintegrate("kf", json::array({0.0, 0.3, 0.6}));
  pre["method"] = {{"propagator", "euler"}};
  const json p = {{"noise", kNoise}, {"imu", CsvImu(csv, "s")}, {"tasks", {pre}}};
  const std::string pipeline = tmp.write("p.json", p.dump());
  ASSERT_EQ(
      RunImuconv("run " + ShellQuote(pipeline) + " -o " + ShellQuote(tmp.file("out.json")), tmp)
          .exit_code,
      0);
  const json out = ReadJson(tmp.file("out.json"));
  tmp.write("M.json", json{{"time_origin_ns", out["time_origin_ns"]},
                           {"measurements", out["tasks"][0]["measurements"]}}
                          .dump());
  const std::string fixture = std::string(IMUCONV_BINARY_DIR) + "/tests/fixtures/override";
  const auto r = RunImuconv("--plugin-dir " + ShellQuote(fixture) +
                                " --allow-plugin-override check " + ShellQuote(tmp.file("M.json")) +
                                " --pipeline " + ShellQuote(pipeline) + " --json",
                            tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json report = json::parse(r.out);
  EXPECT_EQ(report["verdict"], "consistent");
  ASSERT_EQ(report["measurements"].size(), 2u);
  for (const auto& m : report["measurements"]) {
    ASSERT_TRUE(m.contains("not_applicable")) << m.dump();
    ASSERT_EQ(m["not_applicable"].size(), 1u);
    EXPECT_EQ(m["not_applicable"][0]["scheme"], "rk4");
    EXPECT_TRUE(Has(m["not_applicable"][0]["reason"].get<std::string>(),
                    "fixture claims_rk4: not an integrator"));
    EXPECT_EQ(m["best"]["scheme"], "euler");
  }
}

}  // namespace
