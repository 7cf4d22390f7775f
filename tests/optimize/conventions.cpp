// The optimum does not depend on the chart the solver steps in (ceres-api.md's design rules:
// every cost is a function of the states alone; only the manifold changes): on 3 s of the EuRoC
// slice, every registered state convention gives the same keyframe states to 1e-8.
#include <gtest/gtest.h>

#include "../cli/euroc_slice.h"
#include "../support/imuconv_test.h"
#include "imuconv/optimize/optimize.h"
#include "imuconv/optimize/optimize_input.h"
#include "imuconv/so3.h"

namespace {

using namespace imuconv;
using imuconv::test::Plugins;

TEST(OptimizeConventions, SameOptimumInEveryStateConvention) {
  optimize::Input in = optimize::ReadFileInput(test::kEurocSliceImu, test::kEurocSliceGroundTruth);
  // A short slice: the first 3 s of both (the solve per convention stays well under a second).
  const double t_end = in.imu.samples.front().t + 3.0;
  while (in.imu.samples.back().t > t_end) in.imu.samples.pop_back();
  while (in.poses.t.back() > t_end + 0.1) {
    in.poses.t.pop_back();
    in.poses.x.pop_back();
  }
  optimize::Options o;
  o.keyframe_step = 0.25;
  o.noise = ImuNoise{1.6968e-04, 2.0e-3, 1.9393e-05, 3.0e-3};  // EuRoC's datasheet densities
  o.covariance = false;  // the optimum is compared, not the covariances
  o.convention = "left";
  const optimize::Result ref = optimize::RunOptimize(Plugins(), in.imu, in.poses, o);
  ASSERT_TRUE(ref.converged) << ref.solver_message;
  ASSERT_GE(ref.keyframes.size(), 10u);
  for (const std::string& c : Plugins().ids(PluginKind::StateConvention)) {
    if (c == "left") continue;
    o.convention = c;
    const optimize::Result r = optimize::RunOptimize(Plugins(), in.imu, in.poses, o);
    ASSERT_TRUE(r.converged) << c << ": " << r.solver_message;
    ASSERT_EQ(r.keyframes.size(), ref.keyframes.size());
    // 1e-8 (the issue's): the solves stop on a relative step or cost change of 1e-12
    // (optimize.cpp), far below it; a chart-dependent cost would differ by the noise's size,
    // 1e-4 and more.
    for (std::size_t k = 0; k < r.keyframes.size(); ++k) {
      const ImuState &a = r.keyframes[k].x, &b = ref.keyframes[k].x;
      EXPECT_LT(so3::Log(b.R.transpose() * a.R).norm(), 1e-8) << c << " keyframe " << k;
      EXPECT_LT((a.p - b.p).norm(), 1e-8) << c << " keyframe " << k;
      EXPECT_LT((a.v - b.v).norm(), 1e-8) << c << " keyframe " << k;
      EXPECT_LT((a.bg - b.bg).norm(), 1e-8) << c << " keyframe " << k;
      EXPECT_LT((a.ba - b.ba).norm(), 1e-8) << c << " keyframe " << k;
    }
  }
}

}  // namespace
