// The optimum does not depend on the chart the solver steps in (ceres-api.md's design rules:
// every cost is a function of the states alone; only the manifold changes): on 3 s of the EuRoC
// slice, every registered state convention gives the same keyframe states to 1e-8.
#include <gtest/gtest.h>

#include "../cli/euroc_slice.h"
#include "../support/imuconv_test.h"
#include "../support/scale_aware.h"
#include "imuconv/optimize/optimize.h"
#include "imuconv/optimize/optimize_input.h"
#include "imuconv/so3.h"

namespace {

using namespace imuconv;
using imuconv::test::Plugins;

// The first 3 s of the slice's IMU data and poses (a solve per convention well under a second).
optimize::Input ShortSlice() {
  optimize::Input in = optimize::ReadFileInput(test::kEurocSliceImu, test::kEurocSliceGroundTruth);
  const double t_end = in.imu.samples.front().t + 3.0;
  while (in.imu.samples.back().t > t_end) in.imu.samples.pop_back();
  while (in.poses.t.back() > t_end + 0.1) {
    in.poses.t.pop_back();
    in.poses.x.pop_back();
  }
  return in;
}

optimize::Options ShortSliceOptions() {
  optimize::Options o;
  o.keyframe_step = 0.25;
  o.noise = ImuNoise{1.6968e-04, 2.0e-3, 1.9393e-05, 3.0e-3};  // EuRoC's datasheet densities
  o.convention = "left";
  return o;
}

TEST(OptimizeConventions, SameOptimumInEveryStateConvention) {
  const optimize::Input in = ShortSlice();
  optimize::Options o = ShortSliceOptions();
  o.covariance = false;  // the optimum is compared here, the covariances below
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

// Each keyframe's covariance is in the tangent space of the solver's chart: the left chart's,
// carried into it by the registry's conversion at the estimate, J cov_left J^T.
TEST(OptimizeConventions, CovarianceIsInTheSolversChart) {
  const optimize::Input in = ShortSlice();
  optimize::Options o = ShortSliceOptions();
  const optimize::Result ref = optimize::RunOptimize(Plugins(), in.imu, in.poses, o);
  ASSERT_TRUE(ref.covariance_ok) << ref.covariance_message;
  for (const std::string& c : Plugins().ids(PluginKind::StateConvention)) {
    if (c == "left") continue;
    o.convention = c;
    const optimize::Result r = optimize::RunOptimize(Plugins(), in.imu, in.poses, o);
    ASSERT_TRUE(r.covariance_ok) << c << ": " << r.covariance_message;
    for (std::size_t k = 0; k < r.keyframes.size(); ++k) {
      const Mat15 expected =
          Plugins().convert_covariance("left", c, ref.keyframes[k].x, ref.keyframes[k].cov);
      // On the correlation scale: the two solves' states differ by < 1e-8 (above), which moves
      // the Jacobians and so the covariances by about that relatively; 1e-6 leaves room for the
      // QR's rounding and fails a chart or block order that is not the convention's (errors of
      // order one).
      const test::ScaledDiff d = test::CorrelationScaleDiff(expected, r.keyframes[k].cov);
      EXPECT_LT(d.d, 1e-6) << c << " keyframe " << k << " at (" << d.row << ", " << d.col << ")";
    }
  }
}

}  // namespace
