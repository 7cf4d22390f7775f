// The flags of `imuconv optimize` reach its options: the program, on the bundled slice, refuses
// what the option parser and the command's own checks refuse, with exit 2 and the flag named.
#include <gtest/gtest.h>

#include "../cli/euroc_slice.h"
#include "../pipeline/pipeline_test_util.h"

namespace {

using namespace imuconv::test;

TEST(OptimizeCommandLine, FlagsAreCheckedByName) {
  const TempDir tmp;
  const std::string noise = tmp.write("noise.json", nlohmann::json{{"noise", kEurocNoise}}.dump());
  const std::string inputs = "optimize --imu " + ShellQuote(kEurocSliceImu) + " --poses " +
                             ShellQuote(kEurocSliceGroundTruth) + " --noise " + ShellQuote(noise);
  // Each: the arguments after the inputs, and what the message must name.
  for (const auto& [args, named] : std::vector<std::pair<std::string, std::string>>{
           {"--keyframe-step 1 --pose-sigma 0.01", "--pose-sigma: give two numbers"},
           {"--keyframe-step nan", "--keyframe-step"},
           {"--pose-sigma 0.01,0.01", "--keyframe-step is required"},
           {"--keyframe-step 1 --reintegrate-gyro 0", "--reintegrate-gyro"},
           {"--keyframe-step 1 --residual vins", "--residual: gtsam or forster"},
           {"--keyframe-step 1 --max-rounds 0", "--max-rounds"}}) {
    const CommandResult r = RunImuconv(inputs + " " + args, tmp);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << args;
    EXPECT_NE(r.err.find(named), std::string::npos) << args << "\n" << r.err;
  }
  const CommandResult ok = RunImuconv(inputs + " --keyframe-step 2 --pose-sigma 0.02,0.02", tmp);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("solver: converged"), std::string::npos) << ok.out;
}

}  // namespace
