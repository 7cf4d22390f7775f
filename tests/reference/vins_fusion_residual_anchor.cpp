// VINS-Fusion's IMU factor against its own numbers (tests/data/reference/anchors/vins-fusion,
// README.md there): IntegrationBase::evaluate() and IMUFactor::Evaluate on each of the ten
// reference cases, at the linearization bias (`factor`) and at a changed start bias
// (`bias_correction`), against kernels/vins_fusion_residual.h on imuconv's own IntegrationBase
// state (kernels/vins_fusion.h, reproduced in vins_fusion_anchor.cpp). The factor's inputs
// (state_i, state_j) are the anchor's own.
//
// Tolerances. Every raw field: anchors.h's 1e-8 by the note's metric (relative above 1e-4,
// absolute below): the same formulas on an IntegrationBase state that agrees to round-off.
// The whitened fields (sqrt_info, whitened residual and Jacobians): 1e-5. sqrt_info is the
// Cholesky factor of the covariance's inverse, and the covariance's condition number is
// about 1e9, so the covariance's own round-off (about 1e-15 relative) becomes up to about
// 1e-7 relative in sqrt_info (issue 12; measured below).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "anchor_field_diffs.h"
#include "anchor_members.h"
#include "anchors.h"
#include "imuconv/kernels/vins_fusion.h"
#include "imuconv/kernels/vins_fusion_residual.h"
#include "imuconv_test.h"
#include "reference_case.h"

namespace {

using namespace imuconv;
using namespace imuconv::kernels;
using namespace imuconv::test;  // DataPath, JsonMatrix, MaxEntryDiff, the anchors' bounds

constexpr double kWhitenedTol = 1e-5;

VinsFusionFactorState FactorState(const nlohmann::json& s) {
  VinsFusionFactorState x;
  x.Q = JsonQuaternionWxyz(s.at("Q_wxyz"));
  IMUCONV_READ_ANCHOR_MEMBERS(JsonVec3, s, x, (P)(V)(Ba)(Bg));
  return x;
}

/// The worst metric difference of each of IMUFactor::Evaluate's five outputs against the
/// anchor's object `j`, printed under `label` and held to `tol`.
void ExpectFactorOutput(const nlohmann::json& j, const VinsFusionFactorOutput& o, double tol,
                        const std::string& label) {
  const double d_r = MaxEntryDiff(JsonMatrix(j.at("residual")), o.residual);
  const double d_pi = MaxEntryDiff(JsonMatrix(j.at("jacobian_pose_i")), o.jacobian_pose_i);
  const double d_sbi =
      MaxEntryDiff(JsonMatrix(j.at("jacobian_speedbias_i")), o.jacobian_speedbias_i);
  const double d_pj = MaxEntryDiff(JsonMatrix(j.at("jacobian_pose_j")), o.jacobian_pose_j);
  const double d_sbj =
      MaxEntryDiff(JsonMatrix(j.at("jacobian_speedbias_j")), o.jacobian_speedbias_j);
  std::printf("  %-34s residual %.2g pose_i %.2g speedbias_i %.2g pose_j %.2g speedbias_j %.2g\n",
              label.c_str(), d_r, d_pi, d_sbi, d_pj, d_sbj);
  EXPECT_LE(d_r, tol) << label << " residual";
  EXPECT_LE(d_pi, tol) << label << " jacobian_pose_i";
  EXPECT_LE(d_sbi, tol) << label << " jacobian_speedbias_i";
  EXPECT_LE(d_pj, tol) << label << " jacobian_pose_j";
  EXPECT_LE(d_sbj, tol) << label << " jacobian_speedbias_j";
}

class VinsFusionResidualAnchor : public AnchorCaseTest {
 protected:
  VinsFusionResidualAnchor() : AnchorCaseTest("vins-fusion") {}
  void SetUp() override {
    // As in vins_fusion_anchor.cpp: the case's densities as ACC_N..GYR_W, its start biases
    // as the linearization point, G = -gravity.
    m_.linearized_ba = case_.x_s.ba;
    m_.linearized_bg = case_.x_s.bg;
    m_.G = JsonVec3(inputs_.at("G"));
    ASSERT_EQ(m_.G, Vec3(-case_.gravity));
    ASSERT_TRUE(IntegrateVinsFusion(AnchorInput(case_, case_.x_s.bg, case_.x_s.ba),
                                    VinsNoiseMapping::kAsConfigured, m_.pre)
                    .ok());
  }
  VinsFusionMeasurement m_;
};

TEST_P(VinsFusionResidualAnchor, FactorAtTheLinearizationBiasIsVinsFusionOwn) {
  const nlohmann::json& f = anchor_.at("factor");
  const VinsFusionFactorState i = FactorState(f.at("state_i")), j = FactorState(f.at("state_j"));
  const std::string id = GetParam();
  const double d_eval =
      MaxEntryDiff(JsonMatrix(f.at("evaluate_residual")), VinsFusionEvaluate(m_, i, j));
  std::printf("  %-34s evaluate_residual %.2g\n", id.c_str(), d_eval);
  EXPECT_LE(d_eval, kAnchorMetricTol);
  const VinsFusionFactorOutput raw = VinsFusionRawFactor(m_, i, j);
  ExpectFactorOutput(f.at("raw"), raw, kAnchorMetricTol, id + " raw");

  Mat15 sqrt_info;
  ASSERT_TRUE(VinsFusionSqrtInfo(m_.pre.covariance, sqrt_info).ok());
  const double d_info = MaxEntryDiff(JsonMatrix(f.at("sqrt_info")), sqrt_info);
  std::printf("  %-34s sqrt_info %.2g\n", id.c_str(), d_info);
  EXPECT_LE(d_info, kWhitenedTol);
  ExpectFactorOutput(f.at("whitened"), VinsFusionWhiten(raw, sqrt_info), kWhitenedTol,
                     id + " whitened");
  // The whitening of the anchor's own raw outputs with the anchor's own sqrt_info is its
  // whitened output to round-off: what is left above is sqrt_info's conditioning alone.
  VinsFusionFactorOutput anchor_raw;
  anchor_raw.residual = JsonMatrix(f.at("raw").at("residual"));
  anchor_raw.jacobian_pose_i = JsonMatrix(f.at("raw").at("jacobian_pose_i"));
  anchor_raw.jacobian_pose_j = JsonMatrix(f.at("raw").at("jacobian_pose_j"));
  anchor_raw.jacobian_speedbias_i = JsonMatrix(f.at("raw").at("jacobian_speedbias_i"));
  anchor_raw.jacobian_speedbias_j = JsonMatrix(f.at("raw").at("jacobian_speedbias_j"));
  ExpectFactorOutput(f.at("whitened"), VinsFusionWhiten(anchor_raw, JsonMatrix(f.at("sqrt_info"))),
                     kAnchorMetricTol, id + " whitened (anchor's sqrt_info)");
}

TEST_P(VinsFusionResidualAnchor, FactorAtANewBiasIsVinsFusionOwn) {
  const nlohmann::json& bc = anchor_.at("bias_correction");
  const nlohmann::json& fo = bc.at("first_order");
  const Vec3 ba_new = JsonVec3(bc.at("Ba_new")), bg_new = JsonVec3(bc.at("Bg_new"));
  // The README's construction: the case's start bias plus its bias_delta.
  const nlohmann::json delta = CaseJson(GetParam()).at("bias_delta");
  ASSERT_EQ(ba_new, Vec3(case_.x_s.ba + JsonVec3(delta.at("ba"))));
  ASSERT_EQ(bg_new, Vec3(case_.x_s.bg + JsonVec3(delta.at("bg"))));
  const VinsFusionCorrectedDelta c = VinsFusionCorrect(m_, ba_new, bg_new);
  const std::string id = GetParam();
  const double d_p = MaxEntryDiff(JsonMatrix(fo.at("corrected_delta_p")), c.delta_p);
  const double d_v = MaxEntryDiff(JsonMatrix(fo.at("corrected_delta_v")), c.delta_v);
  const double d_q =
      MaxEntryDiff(JsonMatrix(fo.at("corrected_delta_q_wxyz_unnormalized")),
                   Eigen::Vector4d(c.delta_q.w(), c.delta_q.x(), c.delta_q.y(), c.delta_q.z()));
  const VinsFusionFactorState i = FactorState(bc.at("state_i")),
                              j = FactorState(anchor_.at("factor").at("state_j"));
  ASSERT_EQ(i.Ba, ba_new);
  ASSERT_EQ(i.Bg, bg_new);
  const double d_eval =
      MaxEntryDiff(JsonMatrix(bc.at("evaluate_residual")), VinsFusionEvaluate(m_, i, j));
  std::printf("  %-34s first_order p %.2g q %.2g v %.2g | evaluate_residual %.2g\n", id.c_str(),
              d_p, d_q, d_v, d_eval);
  for (const double d : {d_p, d_q, d_v, d_eval}) EXPECT_LE(d, kAnchorMetricTol);
  ExpectFactorOutput(bc.at("raw"), VinsFusionRawFactor(m_, i, j), kAnchorMetricTol,
                     id + " new bias raw");
}

// The raw Jacobians against central differences of evaluate() through the increments Ceres
// applies: p + dp and q (x) deltaQ(dtheta) normalized for a pose, additive for [v, ba, bg].
//
// Tolerance. Step h = 1e-6. The residual's terms reach |G T^2/2| = 490 m (T = 10 s), so
// rounding alone gives about 2.2e-16 x 490 / (2 h) = 5e-8 per entry; the third-order
// truncation h^2/6 |r'''| is below 1e-9 (|r'''| < 1e3). Bound: 1e-6 absolute, measured
// below (the anchors README reports upstream's own agreement as <= 2e-7).
constexpr double kVinsFdStep = 1e-6;
constexpr double kVinsFdTol = 1e-6;

enum class Block { kPoseI, kSpeedBiasI, kPoseJ, kSpeedBiasJ };

/// d evaluate() / d increment of one parameter block, by central differences.
Eigen::MatrixXd NumericJacobian(const VinsFusionMeasurement& m, const VinsFusionFactorState& i,
                                const VinsFusionFactorState& j, Block block) {
  const bool pose = block == Block::kPoseI || block == Block::kPoseJ;
  const int n = pose ? 6 : 9;
  Eigen::MatrixXd J(15, n);
  for (int k = 0; k < n; ++k) {
    Vec15 r[2];
    for (int s = 0; s < 2; ++s) {
      const double h = s == 0 ? kVinsFdStep : -kVinsFdStep;
      VinsFusionFactorState a = i, b = j;
      VinsFusionFactorState& x = (block == Block::kPoseI || block == Block::kSpeedBiasI) ? a : b;
      Eigen::Matrix<double, 9, 1> d = Eigen::Matrix<double, 9, 1>::Zero();
      d[k] = h;
      if (pose) {
        x.P += d.head<3>();
        const Vec3 half = 0.5 * d.segment<3>(3);
        x.Q = (x.Q * Eigen::Quaterniond(1.0, half.x(), half.y(), half.z())).normalized();
      } else {
        x.V += d.head<3>();
        x.Ba += d.segment<3>(3);
        x.Bg += d.segment<3>(6);
      }
      r[s] = VinsFusionEvaluate(m, a, b);
    }
    J.col(k) = (r[0] - r[1]) / (2.0 * kVinsFdStep);
  }
  return J;
}

Eigen::MatrixXd Analytic(const VinsFusionFactorOutput& o, Block block) {
  switch (block) {
    case Block::kPoseI:
      return o.jacobian_pose_i.leftCols<6>();
    case Block::kSpeedBiasI:
      return o.jacobian_speedbias_i;
    case Block::kPoseJ:
      return o.jacobian_pose_j.leftCols<6>();
    case Block::kSpeedBiasJ:
      return o.jacobian_speedbias_j;
  }
  return {};
}

TEST_P(VinsFusionResidualAnchor, RawJacobiansAreCentralDifferencesAtTheLinearizationBias) {
  const nlohmann::json& f = anchor_.at("factor");
  const VinsFusionFactorState i = FactorState(f.at("state_i")), j = FactorState(f.at("state_j"));
  const VinsFusionFactorOutput raw = VinsFusionRawFactor(m_, i, j);
  double worst = 0.0;
  for (const Block b : {Block::kPoseI, Block::kSpeedBiasI, Block::kPoseJ, Block::kSpeedBiasJ})
    worst =
        std::max(worst, (NumericJacobian(m_, i, j, b) - Analytic(raw, b)).cwiseAbs().maxCoeff());
  std::printf("  %-13s FD at the linearization bias: %.2g abs\n", GetParam(), worst);
  EXPECT_LE(worst, kVinsFdTol);
  // Column 6 of the pose blocks (q.w) is zero, as upstream fills it.
  EXPECT_TRUE(raw.jacobian_pose_i.col(6).isZero(0.0));
  EXPECT_TRUE(raw.jacobian_pose_j.col(6).isZero(0.0));
}

// At a start bias away from the linearization point the corrected delta_q is not a unit
// quaternion and two blocks are upstream's approximations (vins_fusion_residual.h):
//  - pose_i (theta, theta) treats c_q as unit: it is the derivative times |c_q|^2, so after
//    dividing by |c_q|^2 it is held to the FD bound;
//  - speedbias_i (theta, bg) uses the uncorrected delta_q: its distance from the derivative
//    is of first order in phi = J_theta,bg dbg. Bound: moving delta_q to delta_q (x) [1, phi/2]
//    changes each entry of br(Qleft(.)) by at most |phi|/2 (|q| = 1) and each entry of the
//    product with J_theta,bg by at most |phi|/2 x 3 max|J_theta,bg|; the deltaQ's norm adds a
//    term of order |phi|^2. That bound is asserted and the measured size printed.
// Everything else is an exact derivative and held to the FD bound.
TEST_P(VinsFusionResidualAnchor, RawJacobiansAtANewBiasExactBlocksAndUpstreamApproximations) {
  const nlohmann::json& bc = anchor_.at("bias_correction");
  const VinsFusionFactorState i = FactorState(bc.at("state_i")),
                              j = FactorState(anchor_.at("factor").at("state_j"));
  const VinsFusionFactorOutput raw = VinsFusionRawFactor(m_, i, j);
  const Eigen::Quaterniond c_q = VinsFusionCorrect(m_, i.Ba, i.Bg).delta_q;
  const Mat3 J_tbg = m_.pre.jacobian.block<3, 3>(3, 12);
  const double phi = (J_tbg * (i.Bg - m_.linearized_bg)).norm();

  double exact = 0.0, approx_bg = 0.0;
  for (const Block b : {Block::kPoseI, Block::kSpeedBiasI, Block::kPoseJ, Block::kSpeedBiasJ}) {
    const Eigen::MatrixXd fd = NumericJacobian(m_, i, j, b);
    Eigen::MatrixXd an = Analytic(raw, b);
    if (b == Block::kPoseI) an.block<3, 3>(3, 3) /= c_q.squaredNorm();
    if (b == Block::kSpeedBiasI) {
      approx_bg = (fd.block<3, 3>(3, 6) - an.block<3, 3>(3, 6)).cwiseAbs().maxCoeff();
      an.block<3, 3>(3, 6) = fd.block<3, 3>(3, 6);  // judged separately
    }
    exact = std::max(exact, (fd - an).cwiseAbs().maxCoeff());
  }
  const double bound = 1.5 * phi * J_tbg.cwiseAbs().maxCoeff() +
                       phi * phi * J_tbg.cwiseAbs().maxCoeff() + kVinsFdTol;
  std::printf(
      "  %-13s FD at the new bias: exact blocks %.2g abs | upstream's d r_theta/d bg %.2g abs "
      "(|phi| = %.2g, "
      "bound %.2g), |c_q|^2 - 1 = %.2g\n",
      GetParam(), exact, approx_bg, phi, bound, c_q.squaredNorm() - 1.0);
  EXPECT_LE(exact, kVinsFdTol);
  EXPECT_LE(approx_bg, bound);
}

INSTANTIATE_TEST_SUITE_P(Reference, VinsFusionResidualAnchor,
                         ::testing::ValuesIn(kReferenceCaseIds), CaseTestName);

}  // namespace
