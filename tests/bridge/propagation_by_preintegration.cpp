// Paper, section 3.2: Phi_e|s and Sigma_e|s from a preintegrated measurement, in any state
// convention, against central differences of the full nonlinear prediction and against the
// propagator the measurement came from.
#include <gtest/gtest.h>

#include "imuconv/bridge.h"
#include "imuconv/numeric.h"
#include "imuconv_test.h"
#include "synthetic.h"

namespace {

using namespace imuconv;
using imuconv::test::Plugins;

struct Scenario {
  std::vector<ImuSample> imu = test::SmoothImu(1.0);
  SampleWindow w;
  ImuState x_s;
  Mat15 cov_left;
  Vec3 g = Vec3(0, 0, -9.81);
  Scenario() {
    EXPECT_TRUE(MakeWindow(imu.data(), imu.size(), imu.front().t, imu.back().t, w).ok());
    x_s.R = so3::Exp(Vec3(0.3, -1.1, 0.7));
    x_s.p = Vec3(3, -2, 1);
    x_s.v = Vec3(0.5, 1.5, -0.2);
    x_s.bg = Vec3(0.01, -0.02, 0.005);
    x_s.ba = Vec3(0.1, 0.05, -0.2);
    Eigen::Matrix<double, 15, 15> A = Eigen::Matrix<double, 15, 15>::Random();
    cov_left = 1e-3 * (A * A.transpose() + 15 * Mat15::Identity());
  }
};

class ByPreintegration : public ::testing::TestWithParam<const char*> {};

TEST_P(ByPreintegration, PhiMatchesCentralDifferencesOfThePrediction) {
  // The start bias differs from the measurement's bias estimate, so the first-order bias
  // correction and its curvature are exercised.
  Scenario s;
  const Preintegrated m = PreintegrateByPropagation(Plugins(), "rk4", s.w, s.x_s.bg - Vec3(2e-3, 1e-3, -1e-3),
                                                    s.x_s.ba + Vec3(0.02, -0.01, 0.03), test::TestNoise());
  const std::string conv = GetParam();
  const auto c = Plugins().state_convention(conv);
  const PropagationResult r = PropagateByPreintegration(Plugins(), m, s.x_s, Mat15::Identity(), conv, s.g);
  const Mat15 num = CentralJacobian([&](const Vec15& e, Vec15& out) {
    ImuState xs2;
    c->retract(s.x_s, e, xs2);
    const PropagationResult r2 = PropagateByPreintegration(Plugins(), m, xs2, Mat15::Identity(), conv, s.g);
    c->local(r.x_e, r2.x_e, out);
  });
  // h = 1e-6 central differences of a map with O(1..10) second derivatives: ~1e-9 relative.
  EXPECT_LT(test::RelErr(r.Phi, num), 1e-6) << conv << "\n" << r.Phi - num;
}

TEST_P(ByPreintegration, AgreesWithThePropagatorItCameFrom) {
  // rk4's Phi and covariance come from its linearised ODE, the prediction's from the exact
  // derivative of the prediction equations with the same rk4 increments: they agree up to
  // rk4's truncation error (~1e-10 relative at 200 Hz over 1 s); 1e-7 leaves margin.
  Scenario s;
  const std::string conv = GetParam();
  const Mat15 cov_conv = Plugins().convert_covariance("left", conv, s.x_s, s.cov_left);
  const Preintegrated m = PreintegrateByPropagation(Plugins(), "rk4", s.w, s.x_s.bg, s.x_s.ba, test::TestNoise());
  const PropagationResult a = PropagateByPreintegration(Plugins(), m, s.x_s, cov_conv, conv, s.g);
  PropagationInput in;
  in.x_s = s.x_s;
  in.cov_s = cov_conv;
  in.noise = test::TestNoise();
  in.gravity = s.g;
  in.window = s.w;
  const PropagationResult b = Plugins().propagate("rk4", conv, in);
  Vec15 d;
  Plugins().state_convention(conv)->local(b.x_e, a.x_e, d);
  EXPECT_LT(d.cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(test::RelErr(a.Phi, b.Phi), 1e-7) << conv;
  EXPECT_LT(test::RelErr(a.cov, b.cov), 1e-7) << conv;
}

INSTANTIATE_TEST_SUITE_P(Conventions, ByPreintegration,
                         ::testing::Values("left", "gtsam_navstate", "gtsam_pose3_vel", "forster", "openvins_jpl",
                                           "right_invariant_se23", "left_invariant_se23"));

}  // namespace
