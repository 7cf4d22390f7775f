// Residuals (paper, section 3.3): Jacobians with respect to the start and end states in
// several state conventions against central differences of the full residual, the
// increment Jacobian against the paper's closed forms, and the chain-rule covariance.
#include <gtest/gtest.h>

#include "imuconv/bridge.h"
#include "imuconv/numeric.h"
#include "imuconv/reference_charts.h"
#include "imuconv_test.h"
#include "synthetic.h"

namespace {

using namespace imuconv;
using imuconv::test::Plugins;

/// The shared scenario with a measurement over its window and an end state x_e.
struct ResidualScenario : test::SmoothScenario {
  ImuState x_e;
  Preintegrated m;
  ResidualScenario() {
    // Bias estimate of the measurement differs from x_s's: the correction is exercised.
    m = PreintegrateByPropagation(Plugins(), "euler", w, x_s.bg + Vec3(1e-3, -2e-3, 1e-3),
                                  x_s.ba + Vec3(-0.01, 0.02, 0.01), test::TestNoise());
    // An end state near (not at) the prediction.
    const ImuState pred = Predict(x_s, m.delta, m.dt, g);
    Vec15 d;
    d << 0.02, -0.01, 0.03, 0.05, -0.02, 0.01, 0.03, 0.02, -0.04, 1e-3, -2e-3, 5e-4, 0.01, -0.02,
        0.03;
    LeftRetract(pred, d, x_e);
  }
};

using Param = std::tuple<ResidualKind, const char*>;
class ResidualJacobians : public ::testing::TestWithParam<Param> {};

TEST_P(ResidualJacobians, MatchCentralDifferences) {
  ResidualScenario s;
  // Named copies, not a structured binding: lambdas capture them (C++17 does not capture bindings).
  const auto kind = std::get<0>(GetParam());
  const auto conv = std::get<1>(GetParam());
  const auto c = Plugins().state_convention(conv);
  const Residual r = ComputeResidual(Plugins(), kind, s.m, s.x_s, s.x_e, conv, s.g);
  const Mat15 num_start = CentralJacobian([&](const Vec15& e, Vec15& out) {
    ImuState xs2;
    c->retract(s.x_s, e, xs2);
    out = ComputeResidual(Plugins(), kind, s.m, xs2, s.x_e, conv, s.g).r;
  });
  const Mat15 num_end = CentralJacobian([&](const Vec15& e, Vec15& out) {
    ImuState xe2;
    c->retract(s.x_e, e, xe2);
    out = ComputeResidual(Plugins(), kind, s.m, s.x_s, xe2, conv, s.g).r;
  });
  // Central differences (h = 1e-6) of a smooth map with entries up to ~10: ~1e-9 relative.
  EXPECT_LT(test::RelErr(r.H_start, num_start), 1e-6) << conv << "\n" << r.H_start - num_start;
  EXPECT_LT(test::RelErr(r.H_end, num_end), 1e-6) << conv << "\n" << r.H_end - num_end;
}

TEST_P(ResidualJacobians, IncrementJacobianAndCovariance) {
  ResidualScenario s;
  // Named copies, not a structured binding: lambdas capture them (C++17 does not capture bindings).
  const auto kind = std::get<0>(GetParam());
  const auto conv = std::get<1>(GetParam());
  const Residual r = ComputeResidual(Plugins(), kind, s.m, s.x_s, s.x_e, conv, s.g);
  const Mat15 num = CentralJacobian([&](const Vec15& w, Vec15& out) {
    Preintegrated m2 = s.m;
    PreintReferenceRetract(s.m.delta, w, m2.delta);
    out = ComputeResidual(Plugins(), kind, m2, s.x_s, s.x_e, conv, s.g).r;
  });
  EXPECT_LT(test::RelErr(r.H_increment, num), 1e-6);
  // Paper, eq. residual-cov.
  EXPECT_LT(test::RelErr(r.cov, Mat15(r.H_increment * s.m.cov * r.H_increment.transpose())), 1e-14);
}

INSTANTIATE_TEST_SUITE_P(
    KindsAndConventions, ResidualJacobians,
    ::testing::Combine(::testing::Values(ResidualKind::Gtsam, ResidualKind::Forster),
                       ::testing::Values("left", "gtsam_pose3_vel", "gtsam_navstate", "forster",
                                         "right_invariant_se23")));

// The paper's closed forms for d r / d dx_se (GTSAM residual; the bias rows carry +I
// because our bias residual is b_e - b_pred, where the paper writes b_pred - b_e):
//   j chart (gtsam_manifold_jacobian): diag(Jr^{-1}(r_theta), R_e^T R_s, R_e^T R_s, I, I)
//   c chart (gtsam_manifold):         diag(Jr^{-1}(r_theta), M, M, I, I), M = R_e^T R_s dR
// and for Forster's residual in its own chart f: diag(Jl^{-1}(r_theta), I, I, I, I)
// (eq. forster-res-jac). Blocks are in each chart's order [theta, p, v, ba, bg] /
// [theta, p, v, bg, ba]; the bias blocks of the gtsam charts are swapped accordingly.
TEST(ResidualIncrementJacobian, MatchesThePapersClosedForms) {
  ResidualScenario s;
  s.m.bg_hat = s.x_s.bg;  // at the estimate, so the increment is not bias-corrected
  s.m.ba_hat = s.x_s.ba;
  const Residual g =
      ComputeResidual(Plugins(), ResidualKind::Gtsam, s.m, s.x_s, s.x_e, "left", s.g);
  const Residual f =
      ComputeResidual(Plugins(), ResidualKind::Forster, s.m, s.x_s, s.x_e, "left", s.g);
  const Mat3 JrInv = so3::JrInv(g.r.head<3>());
  const Mat3 Ms = s.x_e.R.transpose() * s.x_s.R;
  const Mat3 Mc = Ms * s.m.delta.dR;
  auto expect = [&](const Mat15& H, const char* chart, const Mat3& Rth, const Mat3& M,
                    bool gtsam_bias_order) {
    Mat15 want = Mat15::Zero();
    want.block<3, 3>(0, 0) = Rth;
    want.block<3, 3>(3, 3) = M;
    want.block<3, 3>(6, 6) = M;
    if (gtsam_bias_order) {  // residual rows [bg, ba], chart columns [ba, bg]
      want.block<3, 3>(9, 12).setIdentity();
      want.block<3, 3>(12, 9).setIdentity();
    } else {
      want.block<3, 3>(9, 9).setIdentity();
      want.block<3, 3>(12, 12).setIdentity();
    }
    const Mat15 got = H * Plugins().conversion(chart, "preint_reference", s.m.delta);
    EXPECT_LT(test::RelErr(got, want), 1e-12) << chart << "\n" << got;
  };
  expect(g.H_increment, "gtsam_manifold_jacobian", JrInv, Ms, true);
  expect(g.H_increment, "gtsam_manifold", JrInv, Mc, true);
  expect(f.H_increment, "forster", so3::JlInv(f.r.head<3>()), Mat3::Identity(), false);
}

}  // namespace
