// imuconv optimize, `optimize --pipeline` and the pipeline task against inputs that used to run
// out of memory, blame the noise densities or call a NaN cost converged: each is now refused
// with exit 2, a message naming the option or JSON pointer and what was expected, and no output
// file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "../cli/euroc_slice.h"
#include "../pipeline/pipeline_test_util.h"

namespace {

using namespace imuconv::test;
using nlohmann::json;

bool Mentions(const std::string& s, const std::string& sub) {
  return s.find(sub) != std::string::npos;
}

// The data rows of a EuRoC CSV (header dropped) and its header.
std::vector<std::string> EurocRows(const std::string& path, std::string& header) {
  std::ifstream in(path);
  std::vector<std::string> rows;
  std::string line;
  std::getline(in, header);
  while (std::getline(in, line))
    if (!line.empty()) rows.push_back(line);
  return rows;
}

// The first `count` rows of a EuRoC CSV, then the same rows again 10^15 ns (11.6 days) later: 2 s
// of data, a gap of days, 2 s more.
void WriteWithGap(const std::string& from, const std::string& to, std::size_t count) {
  std::string header;
  const std::vector<std::string> rows = EurocRows(from, header);
  std::ofstream out(to);
  out << header << "\n";
  for (std::size_t i = 0; i < count; ++i) out << rows[i] << "\n";
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t comma = rows[i].find(',');
    out << std::stoll(rows[i].substr(0, comma)) + 1000000000000000LL << rows[i].substr(comma)
        << "\n";
  }
}

// The slice cut to 2 s (401 IMU samples at 200 Hz, 41 poses at 20 Hz) on each side of a gap of
// days, as a pipeline that allows the gap, with one optimize task of `keyframe_step`.
std::string GapPipeline(const TempDir& tmp, double keyframe_step) {
  WriteWithGap(kEurocSliceImu, tmp.file("imu_gap.csv"), 401);
  WriteWithGap(kEurocSliceGroundTruth, tmp.file("gt_gap.csv"), 41);
  json p = EurocSlicePipeline(
      json::array({{{"type", "optimize"}, {"name", "op"}, {"keyframe_step", keyframe_step}}}));
  p["imu"] = {{"format", "euroc"}, {"path", "imu_gap.csv"}, {"allow_gaps", true}};
  p["ground_truth"] = {{"format", "euroc"}, {"path", "gt_gap.csv"}, {"allow_gaps", true}};
  const std::string path = tmp.file("gap.json");
  std::ofstream(path) << p.dump(1);
  return path;
}

std::string SliceFileArgs(const TempDir& tmp) {
  std::ofstream(tmp.file("noise.json")) << json{{"noise", kEurocNoise}}.dump();
  return "--imu " + ShellQuote(kEurocSliceImu) + " --poses " + ShellQuote(kEurocSliceGroundTruth) +
         " --noise " + ShellQuote(tmp.file("noise.json"));
}

void ExpectRefusedWithoutOutput(const CommandResult& r, const std::vector<std::string>& named,
                                const std::string& output) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  for (const std::string& n : named) EXPECT_TRUE(Mentions(r.err, n)) << n << "\n" << r.err;
  EXPECT_FALSE(std::filesystem::exists(output)) << output;
}

// Bug: keyframes every 5 ms over the days of the gap are 2e8 keyframes; the command stored them
// all before any check (2.1 GB, then "out of memory", exit 3; std::bad_alloc in `run`). Now the
// count is checked from span / step before anything is stored.
TEST(OptimizeHostileInput, KeyframesOverAGapOfDaysAreCountedBeforeAnythingIsStored) {
  TempDir tmp;
  const std::string p = GapPipeline(tmp, 0.005);
  const CommandResult cli =
      RunImuconv("optimize --pipeline " + ShellQuote(p) + " --keyframe-step 0.005 -o " +
                     ShellQuote(tmp.file("o.json")),
                 tmp);
  ExpectRefusedWithoutOutput(cli, {"--keyframe-step: 0.005 s", "more than 1000000 keyframes"},
                             tmp.file("o.json"));
  const CommandResult run =
      RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(tmp.file("o2.json")), tmp);
  ExpectRefusedWithoutOutput(run, {"/tasks/0", "more than 1000000 keyframes"}, tmp.file("o2.json"));
}

// Bug: at a step of the median period (0.005 s; the slice's stamps jitter by 64 ns), interval 1
// [0.005, 0.01] lies between the samples at 0.004999936 and 0.010000128 s: one interpolated
// step, whose covariance is singular, reported as "not positive definite (are all four noise
// densities positive?)". Now the interval is named and said to hold no sample.
TEST(OptimizeHostileInput, AnIntervalBetweenTwoSamplesIsNamedNotBlamedOnTheNoise) {
  TempDir tmp;
  const CommandResult r =
      RunImuconv("optimize " + SliceFileArgs(tmp) + " --keyframe-step 0.005 -o " +
                     ShellQuote(tmp.file("o.json")),
                 tmp);
  ExpectRefusedWithoutOutput(
      r,
      {"--keyframe-step: interval 1 [0.005, 0.01] s holds no IMU sample strictly "
       "inside it",
       "V1_01_easy_imu0_slice.csv"},
      tmp.file("o.json"));
  EXPECT_FALSE(Mentions(r.err, "noise densities")) << r.err;
}

// Samples exactly 5 ms apart and keyframes on them: every interval is one step between two
// samples, its ends; none holds a sample strictly inside.
TEST(OptimizeHostileInput, KeyframesOnEverySampleLeaveNoSampleInside) {
  TempDir tmp;
  std::string header;
  const std::vector<std::string> rows = EurocRows(kEurocSliceImu, header);
  const long long t0 = std::stoll(rows[0].substr(0, rows[0].find(',')));
  std::ofstream out(tmp.file("imu_5ms.csv"));
  out << header << "\n";
  for (std::size_t i = 0; i < 1000; ++i)
    out << t0 + 5000000LL * static_cast<long long>(i) << rows[i].substr(rows[i].find(',')) << "\n";
  out.close();
  std::ofstream(tmp.file("noise.json")) << json{{"noise", kEurocNoise}}.dump();
  const CommandResult r =
      RunImuconv("optimize --imu " + ShellQuote(tmp.file("imu_5ms.csv")) + " --poses " +
                     ShellQuote(kEurocSliceGroundTruth) + " --noise " +
                     ShellQuote(tmp.file("noise.json")) + " --keyframe-step 0.005",
                 tmp);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Mentions(r.err, "interval 0 [0, 0.005] s holds no IMU sample strictly inside it"))
      << r.err;
}

// Bug: with the gap allowed, a 1000 s step puts interval 1 [1000, 2000] s inside the gap, and
// that too was blamed on the noise densities, by the command and by the pipeline task.
TEST(OptimizeHostileInput, AnIntervalInAGapIsNamed) {
  TempDir tmp;
  const std::string p = GapPipeline(tmp, 1000.0);
  const std::string said = "interval 1 [1000, 2000] s holds no IMU sample strictly inside it";
  const CommandResult cli =
      RunImuconv("optimize --pipeline " + ShellQuote(p) + " --keyframe-step 1000 -o " +
                     ShellQuote(tmp.file("o.json")),
                 tmp);
  ExpectRefusedWithoutOutput(cli, {said, "imu_gap.csv"}, tmp.file("o.json"));
  const CommandResult run =
      RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(tmp.file("o2.json")), tmp);
  ExpectRefusedWithoutOutput(run, {"/tasks/0", said}, tmp.file("o2.json"));
}

// Bug: a pose sigma of 1e-300 squares to 0, its information to inf, and the solve "converged"
// on a NaN cost with every covariance null (exit 0); 1e-100 gave a cost of 1.6e169 and no
// covariance. Now a sigma below kMinPoseSigma (1e-9) is refused, on the command line and at the
// task's pointer.
TEST(OptimizeHostileInput, APoseSigmaThatOverflowsTheCostIsRefused) {
  TempDir tmp;
  for (const char* sigma : {"1e-300,1e-300", "1e-100,0.01", "0.01,1e-10"}) {
    const CommandResult r =
        RunImuconv("optimize " + SliceFileArgs(tmp) + " --keyframe-step 1.0 --json --pose-sigma " +
                       sigma + " -o " + ShellQuote(tmp.file("o.json")),
                   tmp);
    ExpectRefusedWithoutOutput(r, {"--pose-sigma", "at least 1e-9"}, tmp.file("o.json"));
  }
  CopyEurocSlice(tmp);
  std::ofstream(tmp.file("p.json"))
      << EurocSlicePipeline(json::array({{{"type", "optimize"},
                                          {"name", "op"},
                                          {"keyframe_step", 1.0},
                                          {"pose_sigma", {1e-300, 1e-300}}}}))
             .dump(1);
  const CommandResult run = RunImuconv(
      "run " + ShellQuote(tmp.file("p.json")) + " -o " + ShellQuote(tmp.file("o2.json")), tmp);
  ExpectRefusedWithoutOutput(run, {"/tasks/0/pose_sigma", "1e-9"}, tmp.file("o2.json"));
}

// The bound is usable: at 1e-9 m and rad the solve converges to a finite cost with every
// covariance, and nothing but the command's own lines reaches stderr (no glog banner).
TEST(OptimizeHostileInput, TheSmallestPoseSigmaStillSolves) {
  TempDir tmp;
  const CommandResult r = RunImuconv(
      "optimize " + SliceFileArgs(tmp) + " --keyframe-step 1.0 --json --pose-sigma 1e-9,1e-9", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_TRUE(j["solver"]["converged"].get<bool>());
  EXPECT_TRUE(j["solver"]["final_cost"].is_number()) << j["solver"];
  EXPECT_TRUE(j["covariance"]["computed"].get<bool>()) << j["covariance"];
  EXPECT_TRUE(r.err.empty()) << r.err;
}

}  // namespace
