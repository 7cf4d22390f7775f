// The poses' rotations against the gyro (pipeline::PoseGyroWarnings, docs/imu-plausibility.md,
// "Poses against the gyro"): the EuRoC slice's own ground truth gives no warning; the same
// ground truth with each quaternion written x,y,z,w in the w,x,y,z columns (still unit, so the
// readers accept it) gives one naming the file, from nees (file and pipeline inputs) and run,
// on stderr and in nees's --json "warnings"; a sequence without rotation gives no judgment.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "euroc_slice.h"
#include "imuconv/pipeline/imu_plausibility.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv_test.h"
#include "reordered_quaternions.h"
#include "text_contains.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

TEST(PoseGyroConsistency, NeesWarnsOnReorderedQuaternionsOnly) {
  const TempDir tmp;
  const std::string noise = tmp.write("noise.json", json{{"noise", kEurocNoise}}.dump());
  ExpectWarningOnReorderedPosesOnly(
      tmp, "nees --imu " + ShellQuote(kEurocSliceImu) + " --ground-truth ",
      " --noise " + ShellQuote(noise) + " --windows 1 --method rk4 --json");
}

TEST(PoseGyroConsistency, PipelinesNameTheirGroundTruth) {
  // nees --pipeline and run: the pipeline file and /ground_truth are named. (A run keeps the
  // samples its tasks use: the task spans the slice, so that there are windows to judge.)
  const TempDir tmp;
  CopyEurocSlice(tmp);
  ReorderedGroundTruth(tmp, "data/V1_01_easy_groundtruth_vicon2gt_slice.csv");
  const json tasks = json::array({{{"type", "propagate"},
                                   {"name", "p"},
                                   {"propagator", "rk4"},
                                   {"start", {{"state", "ground_truth"}}},
                                   {"interval", {{"t_start", 1.0}, {"t_end", 19.0}}}}});
  const std::string pf = tmp.write("pipeline.json", EurocSlicePipeline(tasks).dump());
  const CommandResult nees =
      RunImuconv("nees --pipeline " + ShellQuote(pf) + " --windows 1 --method rk4 --json", tmp);
  ASSERT_EQ(nees.exit_code, 0) << nees.err;
  const json out = json::parse(nees.out);
  ASSERT_TRUE(out.contains("warnings")) << nees.out;
  EXPECT_TRUE(Has(out["warnings"][0].get<std::string>(), pf + ": /ground_truth" + kPosesDisagree))
      << out["warnings"];
  const CommandResult run =
      RunImuconv("-q run " + ShellQuote(pf) + " -o " + ShellQuote(tmp.file("out.json")), tmp);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(Has(run.err, "warning: " + pf + ": /ground_truth" + kPosesDisagree)) << run.err;
}

TEST(PoseGyroConsistency, NoRotationNoJudgment) {
  // 20 s at rest (the gyro reads 0) against poses turning 0.3 rad/s about z: all 40 windows
  // disagree by 0.15 rad, but none turns by the gyro, so there is no evidence to judge on.
  std::vector<imuconv::ImuSample> samples(4001);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    samples[k].t = 0.005 * static_cast<double>(k);
    samples[k].accel = imuconv::Vec3(0.0, 0.0, 9.81);
  }
  imuconv::pipeline::GroundTruth poses;
  for (int i = 0; i <= 400; ++i) {
    const double t = 0.05 * i;
    poses.t.push_back(t);
    imuconv::ImuState x;
    x.R = Eigen::AngleAxisd(0.3 * t, imuconv::Vec3::UnitZ()).toRotationMatrix();
    poses.x.push_back(x);
  }
  EXPECT_TRUE(imuconv::pipeline::PoseGyroWarnings(samples, poses, "poses").empty());
  // The same poses against a gyro that turns as they do agree.
  for (auto& s : samples) s.gyro = imuconv::Vec3(0.0, 0.0, 0.3);
  EXPECT_TRUE(imuconv::pipeline::PoseGyroWarnings(samples, poses, "poses").empty());
}

}  // namespace
