// Each restructured command run in this process through its Run<Name>Command (apps/cmd_*.h),
// without CLI11: what a test, a pipeline task or the Python module may call. Each is checked
// against the program given the same options, byte for byte (so the registration maps each flag
// onto the options and nothing else), and on its failures: the exit code, the message on
// stderr, nothing on stdout.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv/cli/cmd_check.h"
#include "imuconv/cli/cmd_experiment.h"
#include "imuconv/cli/cmd_montecarlo.h"
#include "imuconv/cli/cmd_nees.h"
#include "imuconv/cli/exit_codes.h"

namespace {
using namespace imuconv::test;
using imuconv::cli::CommandContext;
using nlohmann::json;

const std::string kCasePath = SourcePath("tests/data/reference/cases/smooth-0.json");
// GTSAM's manifold preintegration of smooth-0, one measurement (examples/data/SOURCE.md).
const std::string kMeasurements =
    SourcePath("examples/data/gtsam_smooth0_manifold.measurements.json");
const std::string kImu = SourcePath("examples/data/V1_01_easy_imu0_slice.csv");
const std::string kGroundTruth =
    SourcePath("examples/data/V1_01_easy_groundtruth_vicon2gt_slice.csv");

bool Has(const std::string& s, const std::string& sub) { return s.find(sub) != std::string::npos; }

// What a Run printed on stdout and stderr, and its exit code.
struct Captured {
  int exit_code = -1;
  std::string out, err;
};

// Runs `run` with std::cout and std::cerr captured (the commands print nowhere else but a
// shard's file, which is not stdout here). The plugins come from the build tree only, as
// RunImuconv clears IMUCONV_PLUGIN_PATH for the program.
template <class Run>
Captured Capture(Run run) {
  unsetenv("IMUCONV_PLUGIN_PATH");
  std::ostringstream out, err;
  std::streambuf* const cout_buf = std::cout.rdbuf(out.rdbuf());
  std::streambuf* const cerr_buf = std::cerr.rdbuf(err.rdbuf());
  Captured c;
  try {
    c.exit_code = run();
  } catch (...) {
    std::cout.rdbuf(cout_buf);
    std::cerr.rdbuf(cerr_buf);
    throw;
  }
  std::cout.rdbuf(cout_buf);
  std::cerr.rdbuf(cerr_buf);
  c.out = out.str();
  c.err = err.str();
  return c;
}

// The program, run with `args`, exits with the code and prints on stdout what the command run
// in-process (`run`) did.
void ExpectTheProgramDoesTheSame(const Captured& run, const std::string& args, const TempDir& tmp) {
  const CommandResult program = RunImuconv(args, tmp);
  EXPECT_EQ(program.exit_code, run.exit_code);
  EXPECT_EQ(program.out, run.out);
}

TEST(CommandRuns, CheckRunsWithoutTheCommandLineAsTheProgramDoes) {
  TempDir tmp;
  imuconv::cli::CheckCommandOptions o;
  o.measurements = kMeasurements;
  o.case_path = kCasePath;
  o.as_json = true;
  o.report_path = tmp.file("check.html");
  const CommandContext ctx;
  const Captured run = Capture([&] { return RunCheckCommand(ctx, o); });
  // GTSAM's own numbers on its own case: consistent, exit 0 (docs/check.md).
  ASSERT_EQ(run.exit_code, imuconv::cli::kExitOk) << run.err;
  const json j = json::parse(run.out);
  EXPECT_EQ(j.at("verdict"), "consistent");
  EXPECT_EQ(j.at("measurements").size(), 1u);
  EXPECT_TRUE(std::filesystem::is_regular_file(o.report_path));
  EXPECT_TRUE(Has(run.err, "wrote " + o.report_path)) << run.err;

  ExpectTheProgramDoesTheSame(run,
                              "check " + ShellQuote(kMeasurements) + " --case " +
                                  ShellQuote(kCasePath) + " --json --report " +
                                  ShellQuote(tmp.file("program.html")),
                              tmp);
}

TEST(CommandRuns, CheckFailuresAreExitCodesAndMessages) {
  TempDir tmp;
  const CommandContext ctx;
  imuconv::cli::CheckCommandOptions o;
  o.measurements = tmp.file("missing.json");
  o.case_path = kCasePath;
  const Captured missing = Capture([&] { return RunCheckCommand(ctx, o); });
  EXPECT_EQ(missing.exit_code, imuconv::cli::kExitBadInput);
  EXPECT_EQ(missing.out, "");  // nothing judged, nothing printed
  EXPECT_TRUE(Has(missing.err, "imuconv: error: " + o.measurements)) << missing.err;
  // The report's destination is refused before any work: an input's own name.
  o.measurements = kMeasurements;
  o.report_path = kCasePath;
  const Captured own_input = Capture([&] { return RunCheckCommand(ctx, o); });
  EXPECT_EQ(own_input.exit_code, imuconv::cli::kExitBadInput);
  EXPECT_TRUE(Has(own_input.err, "is the same file as the input file")) << own_input.err;
  // Neither source of samples: a usage error, the command line's to report (CLI11's way).
  o.case_path.clear();
  EXPECT_THROW((void)RunCheckCommand(ctx, o), imuconv::cli::UsageError);
}

imuconv::cli::MontecarloCommandOptions SmallRun() {
  imuconv::cli::MontecarloCommandOptions o;
  o.case_path = kCasePath;
  o.method = "euler";
  o.trials = 20;
  o.seed = 1;
  o.duration = 0.2;  // 41 samples: the trials take milliseconds
  o.threads = 1;
  return o;
}

TEST(CommandRuns, MontecarloRunsWithoutTheCommandLineAsTheProgramDoes) {
  TempDir tmp;
  imuconv::cli::MontecarloCommandOptions o = SmallRun();
  o.as_json = true;
  const CommandContext ctx;
  const Captured run = Capture([&] { return RunMontecarloCommand(ctx, o); });
  // 0 or 1 is the verdict's to say; either way it is the JSON's.
  ASSERT_TRUE(run.exit_code == 0 || run.exit_code == 1) << run.err;
  const json j = json::parse(run.out);
  EXPECT_EQ(j.at("trials"), 20);
  EXPECT_EQ(j.at("seed"), 1);
  EXPECT_EQ(j.at("verdict") == "consistent", run.exit_code == 0);

  ExpectTheProgramDoesTheSame(
      run,
      "montecarlo --case " + ShellQuote(kCasePath) +
          " --method euler --trials 20 --seed 1 --duration 0.2 --threads 1 --json",
      tmp);
}

TEST(CommandRuns, MontecarloShardsMergeToTheWholeRun) {
  TempDir tmp;
  const CommandContext ctx;
  imuconv::cli::MontecarloCommandOptions whole = SmallRun();
  whole.as_json = true;
  const Captured expected = Capture([&] { return RunMontecarloCommand(ctx, whole); });
  ASSERT_TRUE(expected.exit_code == 0 || expected.exit_code == 1) << expected.err;
  for (const char* k : {"0", "1"}) {
    imuconv::cli::MontecarloCommandOptions shard = SmallRun();
    shard.shard = std::string(k) + "/2";
    shard.shard_output = tmp.file(std::string("shard") + k);
    const Captured written = Capture([&] { return RunMontecarloCommand(ctx, shard); });
    ASSERT_EQ(written.exit_code, 0) << written.err;
    EXPECT_TRUE(Has(written.out, "wrote " + *shard.shard_output))
        << written.out;  // the shard's only output
  }
  imuconv::cli::MontecarloCommandOptions merge;
  merge.merge_files = {tmp.file("shard1"), tmp.file("shard0")};
  merge.as_json = true;
  const Captured merged = Capture([&] { return RunMontecarloCommand(ctx, merge); });
  EXPECT_EQ(merged.exit_code, expected.exit_code) << merged.err;
  EXPECT_EQ(merged.out, expected.out);
}

TEST(CommandRuns, MontecarloRefusalsNameTheOption) {
  const CommandContext ctx;
  // A merge takes none of a run's options, and names the one given. The hidden --noise-scale
  // was named "" before (CLI11's name of an option without a group).
  imuconv::cli::MontecarloCommandOptions merge;
  merge.merge_files = {"a", "b"};
  merge.noise_scale = 2.0;
  const Captured scale = Capture([&] { return RunMontecarloCommand(ctx, merge); });
  EXPECT_EQ(scale.exit_code, imuconv::cli::kExitBadInput);
  EXPECT_EQ(
      scale.err,
      "imuconv: error: --merge takes the run from its shards; --noise-scale is not used with it\n");
  merge.noise_scale.reset();
  merge.shard_output = "x";
  const Captured output = Capture([&] { return RunMontecarloCommand(ctx, merge); });
  EXPECT_TRUE(Has(output.err, "; --output is not used with it")) << output.err;
  // A run misses what it needs; a shard needs its file.
  const Captured missing =
      Capture([&] { return RunMontecarloCommand(ctx, imuconv::cli::MontecarloCommandOptions{}); });
  EXPECT_EQ(missing.exit_code, imuconv::cli::kExitBadInput);
  EXPECT_TRUE(Has(missing.err, "--case (or --pipeline), --method, --trials, --seed: required"))
      << missing.err;
  imuconv::cli::MontecarloCommandOptions shard = SmallRun();
  shard.shard = "0/2";
  const Captured no_file = Capture([&] { return RunMontecarloCommand(ctx, shard); });
  EXPECT_EQ(no_file.exit_code, imuconv::cli::kExitBadInput);
  EXPECT_TRUE(Has(no_file.err, "--shard K/N needs -o FILE")) << no_file.err;
  EXPECT_EQ(no_file.out, "");
}

TEST(CommandRuns, NeesRunsWithoutTheCommandLineAsTheProgramDoes) {
  TempDir tmp;
  const std::string noise = tmp.write("noise.json", json{{"gyro_noise_density", 1.6968e-04},
                                                         {"accel_noise_density", 2.0e-3},
                                                         {"gyro_random_walk", 1.9393e-05},
                                                         {"accel_random_walk", 3.0e-3}}
                                                        .dump());
  imuconv::cli::NeesCommandOptions o;
  o.imu_path = kImu;
  o.ground_truth_path = kGroundTruth;
  o.noise_path = noise;
  o.windows = {0.5, 1.0};
  o.method = "rk4";
  o.as_json = true;
  const CommandContext ctx;
  const Captured run = Capture([&] { return RunNeesCommand(ctx, o); });
  ASSERT_EQ(run.exit_code, imuconv::cli::kExitOk) << run.err;  // nees has no verdict
  const json j = json::parse(run.out);
  EXPECT_EQ(j.at("method"), "rk4");
  EXPECT_EQ(j.at("convention"), "left");  // the option's default, as the flag's
  EXPECT_EQ(j.at("windows").size(), 2u);  // one entry per window length

  ExpectTheProgramDoesTheSame(run,
                              "nees --imu " + ShellQuote(kImu) + " --ground-truth " +
                                  ShellQuote(kGroundTruth) + " --noise " + ShellQuote(noise) +
                                  " --windows 0.5,1 --method rk4 --json",
                              tmp);

  o.convention = "no_such_convention";
  const Captured unknown = Capture([&] { return RunNeesCommand(ctx, o); });
  EXPECT_EQ(unknown.exit_code, imuconv::cli::kExitBadInput);
  EXPECT_TRUE(Has(unknown.err, "--convention: unknown state convention")) << unknown.err;
  EXPECT_EQ(unknown.out, "");
  o.noise_path.clear();
  EXPECT_THROW((void)RunNeesCommand(ctx, o), imuconv::cli::UsageError);
}

TEST(CommandRuns, ExperimentRunsWithoutTheCommandLineAsTheProgramDoes) {
  TempDir tmp;
  imuconv::cli::ExperimentCommandOptions o;
  o.which = "both";
  o.seed = 1;
  o.trials = 2;
  o.duration = 0.1;  // 20 steps a trial: milliseconds
  o.threads = 1;
  o.as_json = true;
  const CommandContext ctx;
  const Captured run = Capture([&] { return RunExperimentCommand(ctx, o); });
  ASSERT_EQ(run.exit_code, imuconv::cli::kExitOk) << run.err;
  const json j = json::parse(run.out);
  EXPECT_EQ(j.at("trials"), 2);
  EXPECT_EQ(j.at("seed"), 1);

  ExpectTheProgramDoesTheSame(
      run, "experiment both --seed 1 --trials 2 --duration 0.1 --threads 1 --json", tmp);

  o.propagator = "no_such_propagator";
  const Captured unknown = Capture([&] { return RunExperimentCommand(ctx, o); });
  EXPECT_EQ(unknown.exit_code, imuconv::cli::kExitBadInput);
  EXPECT_TRUE(Has(unknown.err, "--propagator: unknown propagator")) << unknown.err;
  EXPECT_EQ(unknown.out, "");
}

}  // namespace
