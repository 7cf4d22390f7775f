// imuconv montecarlo's input (issue 23, "Minimal input"): a case needs only /imu and /noise
// (the rest takes its standard value, said on stderr); every missing required key is named
// in one error; --pipeline P.json gives the same samples and noise as a case, over
// --from/--to; and the hostile forms are refused with exit 2, naming what is wrong.
//
// Runs: N = 100 trials over the first 0.2 s (41 samples): milliseconds each. Where a case and
// a pipeline hold the same samples the outputs are compared for equality of the statistics:
// the pipeline's CSV writes each time in milliseconds with 17 significant digits, and read
// back the times may differ from the case's by ~1e-16 s, which moves the statistics by ~1e-13
// relative (rk4 noise cells of (h_k-1 + h_k)/2 and the steps themselves); compared to 1e-9.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"
#include "number_text.h"
#include "reference_case.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;
using nlohmann::json;

const std::string kRun = " --method rk4 --trials 100 --seed 3 --json";

TEST(MontecarloInput, ACaseWithOnlyImuAndNoiseRunsWithStandardValues) {
  const TempDir tmp;
  const json full = CaseJson("smooth-0");
  // The samples, the densities and a zero bias estimate: the standard values of every other
  // key give the same run as the full case with its biases zeroed (montecarlo does not read
  // gravity, the start state's pose and velocity, its covariance, the end perturbation or
  // bias_delta).
  const json minimal = {{"imu", full["imu"]}, {"noise", full["noise"]}};
  json zero_bias = full;
  zero_bias["state_s"]["bg"] = {0.0, 0.0, 0.0};
  zero_bias["state_s"]["ba"] = {0.0, 0.0, 0.0};
  const std::string min_path = tmp.write("minimal.json", minimal.dump());
  const std::string ref_path = tmp.write("zero_bias.json", zero_bias.dump());
  const CommandResult a =
      RunImuconv("montecarlo --case " + ShellQuote(min_path) + " --duration 0.2" + kRun, tmp);
  const CommandResult b =
      RunImuconv("montecarlo --case " + ShellQuote(ref_path) + " --duration 0.2" + kRun, tmp);
  ASSERT_NE(a.exit_code, 2) << a.err;
  ASSERT_NE(b.exit_code, 2) << b.err;
  EXPECT_EQ(json::parse(a.out), json::parse(b.out));
  // The defaults are said, each by its pointer, and only those not given.
  for (const char* ptr :
       {"/gravity", "/state_s/q_wxyz", "/state_s/p", "/state_s/v", "/state_s/bg", "/state_s/ba",
        "/cov_s_left/matrix", "/end_perturbation", "/bias_delta/bg", "/bias_delta/ba"})
    EXPECT_TRUE(Has(a.err, ptr)) << ptr << "\n" << a.err;
  EXPECT_FALSE(Has(b.err, "standard values")) << b.err;
  // With the biases given (as the case has them), they are used: not the zero run.
  json with_bias = minimal;
  with_bias["state_s"] = {{"bg", full["state_s"]["bg"]}, {"ba", full["state_s"]["ba"]}};
  const CommandResult c =
      RunImuconv("montecarlo --case " + ShellQuote(tmp.write("bias.json", with_bias.dump())) +
                     " --duration 0.2" + kRun,
                 tmp);
  const CommandResult d =
      RunImuconv("montecarlo --case " + ShellQuote(DataPath("reference/cases/smooth-0.json")) +
                     " --duration 0.2" + kRun,
                 tmp);
  ASSERT_NE(c.exit_code, 2) << c.err;
  EXPECT_EQ(json::parse(c.out), json::parse(d.out));
  EXPECT_FALSE(Has(c.err, "/state_s/bg")) << c.err;
}

TEST(MontecarloInput, EveryMissingRequiredKeyIsNamedAtOnce) {
  const TempDir tmp;
  const json full = CaseJson("smooth-0");
  json no_noise_values = {{"imu", full["imu"]}, {"noise", {{"accel_noise_density", 0.01}}}};
  const CommandResult r = RunImuconv(
      "montecarlo --case " + ShellQuote(tmp.write("partial.json", no_noise_values.dump())) + kRun,
      tmp);
  EXPECT_EQ(r.exit_code, 2);
  for (const char* ptr :
       {"/noise/gyro_noise_density", "/noise/gyro_random_walk", "/noise/accel_random_walk"})
    EXPECT_TRUE(Has(r.err, ptr)) << ptr << "\n" << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1)
      << r.err;  // one error, all three in it
  const CommandResult empty =
      RunImuconv("montecarlo --case " + ShellQuote(tmp.write("empty.json", "{}")) + kRun, tmp);
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_TRUE(Has(empty.err, "/imu, /noise/gyro_noise_density")) << empty.err;
  // `imuconv refcase` needs every key, and names every missing one at once too.
  json no_gravity = full;
  no_gravity.erase("gravity");
  no_gravity.erase("bias_delta");
  no_gravity["state_s"].erase("q_wxyz");
  const CommandResult ref = RunImuconv(
      "refcase " + ShellQuote(tmp.write("no_gravity.json", no_gravity.dump())) + " -o -", tmp);
  EXPECT_NE(ref.exit_code, 0)
      << ref.err;  // refcase's own exit code for bad input (not montecarlo's)
  EXPECT_TRUE(Has(ref.err, "/gravity, /state_s/q_wxyz, /bias_delta/bg, /bias_delta/ba")) << ref.err;
}

/// A case's samples as a generic CSV (times in ms) and a pipeline reading it with the case's noise.
std::string McCasePipeline(const TempDir& tmp, const json& c) {
  std::string csv = "time_ms,wx,wy,wz,ax,ay,az\n";
  for (const auto& r : c["imu"]) {
    csv += Num17(r[0].get<double>() * 1000.0);
    for (int k = 1; k <= 6; ++k) csv += "," + Num17(r[k].get<double>());
    csv += "\n";
  }
  const std::string csv_path = tmp.write("imu.csv", csv);
  const json p = {
      {"noise", c["noise"]},
      {"imu", CsvImuFromTimeZero(csv_path, "ms", "time_ms")},
      // A pipeline has tasks; montecarlo runs none of them.
      {"tasks",
       json::array(
           {{{"type", "propagate"},
             {"name", "unused"},
             {"propagator", "euler"},
             {"start", {{"state", {{"p", {0, 0, 0}}, {"q_wxyz", {1, 0, 0, 0}}, {"v", {0, 0, 0}}}}}},
             {"interval", {{"t_start", c["imu"][0][0]}, {"t_end", c["imu"][10][0]}}}}})}};
  return tmp.write("pipeline.json", p.dump(1));
}

TEST(MontecarloInput, PipelineOverAnIntervalIsTheCaseOverIt) {
  const TempDir tmp;
  json c = CaseJson("jitter-0");
  for (auto& k : {"bg", "ba"})
    c["state_s"][k] = {0.0, 0.0, 0.0};  // a pipeline's bias estimate is zero
  const std::string case_path = tmp.write("case.json", c.dump());
  const std::string pipeline = McCasePipeline(tmp, c);
  const double t0 = c["imu"][0][0].get<double>();
  char interval[96];
  std::snprintf(interval, sizeof interval, " --from %.17g --to %.17g", t0 + 1.0, t0 + 1.2);
  const CommandResult from_case =
      RunImuconv("montecarlo --case " + ShellQuote(case_path) + interval + kRun, tmp);
  const CommandResult from_pipeline =
      RunImuconv("montecarlo --pipeline " + ShellQuote(pipeline) + interval + kRun, tmp);
  ASSERT_NE(from_case.exit_code, 2) << from_case.err;
  ASSERT_NE(from_pipeline.exit_code, 2) << from_pipeline.err;
  const json a = json::parse(from_case.out), b = json::parse(from_pipeline.out);
  EXPECT_EQ(a["samples"], b["samples"]);
  EXPECT_GT(a["samples"].get<int>(), 30);  // 0.2 s of 3-7 ms steps
  EXPECT_LT(a["samples"].get<int>(), 70);
  for (const char* key : {"nees_mean", "kl", "relative_frobenius", "duration"})
    EXPECT_NEAR(a[key].get<double>(), b[key].get<double>(), 1e-9 * std::abs(a[key].get<double>()))
        << key;
  EXPECT_EQ(a["verdict"], b["verdict"]);

  // Hostile forms: each refused with exit 2 and a message that names the problem.
  struct Bad {
    std::string args, message;
  };
  const std::vector<Bad> bad = {
      {"--case " + ShellQuote(case_path) + " --pipeline " + ShellQuote(pipeline), "not both"},
      {"--pipeline " + ShellQuote(pipeline) + " --from 5 --to 4", "--from before --to"},
      {"--pipeline " + ShellQuote(pipeline) + " --from 1e6 --to 2e6", "samples span"},
      // Inside at one end, outside at the other: refused, not cut to the data.
      {"--pipeline " + ShellQuote(pipeline) + " --from " + std::to_string(t0 + 1.0) + " --to 1e6",
       "--to 1000000: outside the samples of"},
      {"--case " + ShellQuote(case_path) + " --from -1e300", "--from -1e+300: outside the samples"},
      {"--pipeline " + ShellQuote(pipeline) + " --shard 0/2 -o " +
           ShellQuote(tmp.path() + "/s.mcs"),
       "--shard takes --case"},
      {"--pipeline " + ShellQuote(tmp.write("no_imu.json",
                                            [&] {
                                              json p = ReadJson(pipeline);
                                              p.erase("imu");
                                              return p.dump();
                                            }())),
       "/imu"},
  };
  for (const Bad& x : bad) {
    const CommandResult r =
        RunImuconv("montecarlo " + x.args + " --method rk4 --trials 100 --seed 3", tmp);
    EXPECT_EQ(r.exit_code, 2) << x.args << "\n" << r.err;
    EXPECT_TRUE(Has(r.err, x.message)) << x.args << "\n" << r.err;
  }
}

}  // namespace
