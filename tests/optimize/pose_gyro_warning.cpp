// imuconv optimize warns when the poses' rotations disagree with the gyro (a quaternion order
// mistaken: pipeline::PoseGyroWarnings), in --json "warnings" and on stderr, and still solves;
// the slice's own ground truth gives no warning.
#include <gtest/gtest.h>

#include "../cli/euroc_slice.h"
#include "../cli/reordered_quaternions.h"
#include "../pipeline/pipeline_test_util.h"

namespace {

using namespace imuconv::test;

TEST(OptimizePoseGyro, WarnsOnReorderedQuaternionsOnly) {
  const TempDir tmp;
  const std::string noise = tmp.write("noise.json", nlohmann::json{{"noise", kEurocNoise}}.dump());
  ExpectWarningOnReorderedPosesOnly(tmp,
                                    "optimize --imu " + ShellQuote(kEurocSliceImu) + " --poses ",
                                    " --noise " + ShellQuote(noise) + " --keyframe-step 2 --json");
}

}  // namespace
