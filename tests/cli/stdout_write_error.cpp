// A result printed on standard output that cannot be written (a full disk: /dev/full) is an
// error naming standard output, exit 2, for every command, as `run -o -` always was: a script
// doing `imuconv check ... --json > result.json` must not take a lost result for a success.
// Before the fix nothing tested std::cout after the last flush: check --json, nees --json,
// conversion, convert and plugins --json exited 0 with their output lost.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include "euroc_slice.h"
#include "run_from.h"

namespace {
using namespace imuconv::test;

TEST(StdoutWriteError, EveryCommandFailsWhenItsOutputIsLost) {
  if (::access("/dev/full", W_OK) != 0) GTEST_SKIP() << "no writable /dev/full here";
  TempDir tmp;
  const std::string noise = tmp.file("noise.json"), cov = tmp.file("cov.json");
  std::ofstream(noise) << kEurocNoise.dump();
  nlohmann::json identity = nlohmann::json::array();  // a 15x15 covariance as rows
  for (int i = 0; i < 15; ++i) {
    identity.push_back(nlohmann::json::array());
    for (int k = 0; k < 15; ++k) identity[i].push_back(i == k ? 1.0 : 0.0);
  }
  std::ofstream(cov) << identity.dump();
  const std::string state = ShellQuote(SourcePath("examples/hover.state.json"));
  const std::string commands[] = {
      "check " + ShellQuote(SourcePath("examples/data/gtsam_smooth0_manifold.measurements.json")) +
          " --case " + ShellQuote(SourcePath("tests/data/reference/cases/smooth-0.json")) +
          " --json",
      "nees --imu " + ShellQuote(kEurocSliceImu) + " --ground-truth " +
          ShellQuote(kEurocSliceGroundTruth) + " --noise " + ShellQuote(noise) +
          " --windows 1 --method rk4 --json",
      "conversion --from left --to gtsam_navstate --state " + state,
      "convert --what covariance --from left --to gtsam_navstate --state " + state + " --matrix " +
          ShellQuote(cov),
      "plugins --json",
      "plugins",
  };
  for (const std::string& c : commands) {
    SCOPED_TRACE(c);
    // The same command with its output kept succeeds: the failure below is the lost output's.
    const CommandResult kept = RunImuconvFrom(tmp.path(), c, tmp);
    ASSERT_EQ(kept.exit_code, 0) << kept.err;
    ASSERT_FALSE(kept.out.empty());
    const CommandResult lost = RunImuconvFrom(tmp.path(), c, tmp, "/dev/full");
    EXPECT_EQ(lost.exit_code, 2) << lost.err;
    EXPECT_TRUE(Has(lost.err, "imuconv: error: standard output: cannot write")) << lost.err;
    EXPECT_TRUE(Has(lost.err, "No space left on device")) << lost.err;
  }
}

}  // namespace
