// OKVIS2's own numbers (tests/data/reference/anchors/okvis2, README.md there) through the
// plugins and the registry, as a user reaches them: the `okvis2` propagator (ImuError::
// propagation) propagated in the `okvis2` state convention, the `okvis2` preintegrator
// (redoPreintegration) brought into the reference charts by the bridge and expressed back in
// the `okvis2` increment convention, and preintegration by propagation with the `okvis2`
// propagator. okvis2_anchor.cpp holds the kernel itself to the same files; here the plugin
// path's conversions (window knots to okvis::Time, gravity, the charts, J_bias's layout and
// signs) are judged.
//
// Tolerances: anchors.h (1e-8 by the note's metric; covariances also on the correlation scale
// and Jacobians relative to entries above 1e-4 of the largest, at 1e-9): the kernel's own
// round-off against upstream, plus a round trip through `preint_reference` (a product with
// Delta_C and its transpose, ~1e-16 relative).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "anchor_field_diffs.h"
#include "anchors.h"
#include "imuconv/bridge.h"
#include "imuconv_test.h"
#include "scale_aware.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;  // DataPath, JsonMatrix, Plugins, the anchors' bounds

/// The anchor's bias Jacobian of the increment in the `okvis2` chart, J_bias's layout: rows
/// [p, alpha, v], columns [bg, ba], from ImuError's first-order correction (the README's
/// residual: Dq = exp(-dalpha_db_g dbg) (x) Delta_q, so d alpha/d bg = -dalpha_db_g).
Mat96 AnchorBiasJacobian(const nlohmann::json& pre) {
  Mat96 J = Mat96::Zero();
  J.block<3, 3>(0, 0) = JsonMatrix(pre.at("dp_db_g"));
  J.block<3, 3>(0, 3) = -JsonMatrix(pre.at("C_doubleintegral"));
  J.block<3, 3>(3, 0) = -JsonMatrix(pre.at("dalpha_db_g"));
  J.block<3, 3>(6, 0) = JsonMatrix(pre.at("dv_db_g"));
  J.block<3, 3>(6, 3) = -JsonMatrix(pre.at("C_integral"));
  return J;
}

class Okvis2PluginsAnchor : public AnchorCaseTest {
 protected:
  Okvis2PluginsAnchor() : AnchorCaseTest("okvis2") {}
  void SetUp() override {
    // The anchor ran with the case's densities as sigma_*_c and gravity (0, 0, -9.81).
    ASSERT_EQ(inputs_.at("sigma_g_c").get<double>(), case_.noise.gyro_noise_density);
    ASSERT_EQ(inputs_.at("sigma_a_c").get<double>(), case_.noise.accel_noise_density);
    ASSERT_EQ(inputs_.at("sigma_gw_c").get<double>(), case_.noise.gyro_random_walk);
    ASSERT_EQ(inputs_.at("sigma_aw_c").get<double>(), case_.noise.accel_random_walk);
    ASSERT_EQ(Vec3(0.0, 0.0, -inputs_.at("g").get<double>()), case_.gravity);
  }

  /// `o`'s increment and covariance, in OKVIS's chart and order, against ImuError's
  /// preintegration `pre` (Delta_R, acc_doubleintegral, acc_integral, P_delta).
  static void CompareIncrementAndCovariance(const nlohmann::json& pre, const Preintegrated& o,
                                            AnchorFieldDiffs& w) {
    w.Metric("Delta_R", JsonMatrix(pre.at("Delta_R")), o.delta.dR);
    w.Metric("acc_doubleintegral", JsonMatrix(pre.at("acc_doubleintegral")), o.delta.dp);
    w.Metric("acc_integral", JsonMatrix(pre.at("acc_integral")), o.delta.dv);
    w.Covariance("P_delta", JsonMatrix(pre.at("P_delta").at("matrix")), o.cov);
  }
};

TEST_P(Okvis2PluginsAnchor, PropagatorIsOkvisPropagation) {
  PropagationInput in = MakeInput(case_, case_.samples.front().t, case_.samples.back().t);
  in.cov_s.setZero();  // the anchor's covariance is the noise alone
  const PropagationResult r = Plugins().propagate("okvis2", "okvis2", in);
  const nlohmann::json& j = anchor_.at("propagation");
  AnchorFieldDiffs w(std::string(GetParam()) + " okvis2 propagator");
  // The plugin's state holds R alone: the file's quaternion is not compared here.
  w.PropagatedState(j.at("state_end"), {"r", "q_wxyz", "C", "v"}, r.x_e.p, std::nullopt, r.x_e.R,
                    r.x_e.v, r.x_e.bg, r.x_e.ba);
  w.Covariance("covariance", JsonMatrix(j.at("covariance").at("matrix")), r.cov);
  w.Jacobian("jacobian", JsonMatrix(j.at("jacobian").at("matrix")), r.Phi);
  w.Print();

  // With a start covariance, the propagated one is Phi cov_s Phi^T + the noise's (the
  // `left` chart is the same: no conversion on the way).
  in.cov_s = case_.cov_s_left;
  const PropagationResult with_prior = Plugins().propagate("okvis2", "left", in);
  const Mat15 expected = r.Phi * case_.cov_s_left * r.Phi.transpose() + r.cov;
  const ScaledDiff s = CorrelationScaleDiff(expected, with_prior.cov);
  EXPECT_LE(s.d, kAnchorScaledTol) << "at (" << s.row << "," << s.col << ")";
}

TEST_P(Okvis2PluginsAnchor, PreintegratorIsImuErrorPreintegration) {
  const PropagationInput in = MakeInput(case_, case_.samples.front().t, case_.samples.back().t);
  const Preintegrated m =
      PreintegrateNative(Plugins(), "okvis2", in.window, case_.x_s.bg, case_.x_s.ba, case_.noise);
  ASSERT_TRUE(m.in_reference_charts());
  const Preintegrated o = Express(Plugins(), m, "okvis2");
  ASSERT_EQ(o.convention, "okvis2");
  ASSERT_EQ(o.jacobian_convention, "okvis2");
  const nlohmann::json& pre = anchor_.at("imu_error").at("preintegration");
  AnchorFieldDiffs w(std::string(GetParam()) + " okvis2 preintegrator");
  CompareIncrementAndCovariance(pre, o, w);
  w.Jacobian("J_bias", AnchorBiasJacobian(pre), o.J_bias);
  w.Print();
  EXPECT_EQ(o.dt, inputs_.at("Delta_t").get<double>());
  EXPECT_EQ(o.bg_hat, case_.x_s.bg);
  EXPECT_EQ(o.ba_hat, case_.x_s.ba);
}

TEST_P(Okvis2PluginsAnchor, PreintegrationByOkvisPropagation) {
  // The note's section 3.1 with OKVIS's propagation: from the identity, zero gravity, the
  // end state is the increment and the covariance P_delta (propagation and
  // redoPreintegration share the step and, without saturation, its noise). The bias
  // Jacobian differs in one block: propagation sums dt C_k+1 for d alpha/d bg where
  // redoPreintegration sums C_k+1 Jr dt; the others agree.
  const PropagationInput in = MakeInput(case_, case_.samples.front().t, case_.samples.back().t);
  const Preintegrated o =
      Express(Plugins(),
              PreintegrateByPropagation(Plugins(), "okvis2", in.window, case_.x_s.bg, case_.x_s.ba,
                                        case_.noise),
              "okvis2");
  const nlohmann::json& pre = anchor_.at("imu_error").at("preintegration");
  AnchorFieldDiffs w(std::string(GetParam()) + " by okvis2 propagation");
  CompareIncrementAndCovariance(pre, o, w);
  const Mat96 J = AnchorBiasJacobian(pre);
  w.Jacobian("J_bias p rows", J.topRows<3>(), o.J_bias.topRows<3>());
  w.Jacobian("J_bias v rows", J.bottomRows<3>(), o.J_bias.bottomRows<3>());
  w.Print();
  // The alpha-bg block without Jr: Jr = I - [w dt]x/2 + ..., |w| dt <= 0.024 on these cases
  // (4.8 rad/s, 5 ms), so the block is off by about half that at most; and it is off by more
  // than round-off (measured 1.6e-5 to 2.6e-4 of the block: the steps' [w dt]x largely
  // cancel along a path), the one part where OKVIS's two integrations differ.
  const Mat3 ref = J.block<3, 3>(3, 0), got = o.J_bias.block<3, 3>(3, 0);
  const double d = (got - ref).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff();
  std::printf("  %-36s d alpha/d bg without Jr: %.2g of the block\n", GetParam(), d);
  EXPECT_LE(d, 0.02);
  EXPECT_GT(d, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Reference, Okvis2PluginsAnchor, ::testing::ValuesIn(kReferenceCaseIds),
                         CaseTestName);

}  // namespace
