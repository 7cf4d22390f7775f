// `okvis2`: OKVIS2's ImuError::EvaluateWithMinimalJacobians (ethz-mrl/okvis2, okvis_ceres
// ImuError.cpp) as a residual plugin: the raw 15-dim residual [position, 2 vec(Dq (x) q_1^-1
// (x) q_0), velocity, b_0 - b_1] with the first-order bias correction from the
// measurement's linearization bias to x_s's, its Jacobians w.r.t. OKVIS's parameter blocks
// (15x7 poses [x y z qx qy qz qw], 15x9 speed-and-biases [v, bg, ba]) and the minimal ones
// w.r.t. PoseManifold::plus (15x6, [dr, dalpha], C = Exp(dalpha) C), and the information
// OKVIS weights them with (P_delta's pseudo-inverse as it forms it). OKVIS multiplies all of
// them by a square root of the information whose row signs an eigen-solver chooses; those
// are not written (the anchors' README): r^T information r is the squared distance.
// The measurement is expressed in `okvis2` (P_delta's chart, [p, alpha, v, bg, ba] in frame
// S0), from which ImuError's preintegrated quantities follow: Delta_q, acc_doubleintegral and
// acc_integral are the increment, and the bias Jacobians are its J_bias (okvis2_scheme.h).
// Re-integration at a new bias is not the factor's: a preintegrate task at that bias gives
// the measurement OKVIS's repropagation would (tests/pipeline/residual_okvis2.cpp).
// The kernel is core/include/imuconv/kernels/okvis2.h; it agrees with OKVIS2's own numbers on
// the ten reference cases (tests/reference/okvis2_anchor.cpp).
#include <Eigen/Geometry>

#include "imuconv/kernels/okvis2.h"
#include "imuconv/plugin/residual_plugin.h"
#include "imuconv/plugin_abi.h"
#include "jacobian_blocks.h"

namespace {

using namespace imuconv;

/// ImuError's preintegration from a measurement expressed in `okvis2` (J_bias rows [p, alpha,
/// v], columns [bg, ba]: dp_db_g, -C_doubleintegral; -dalpha_db_g, 0; dv_db_g, -C_integral).
kernels::Okvis2Preintegration Okvis2PreintegrationOf(const Preintegrated& m) {
  kernels::Okvis2Preintegration p;
  p.steps = 1;  // integrated (ImuError's redoCounter_ > 0)
  p.Delta_q = Eigen::Quaterniond(m.delta.dR);
  p.acc_doubleintegral = m.delta.dp;
  p.acc_integral = m.delta.dv;
  p.dp_db_g = m.J_bias.block<3, 3>(0, 0);
  p.C_doubleintegral = -m.J_bias.block<3, 3>(0, 3);
  p.dalpha_db_g = -m.J_bias.block<3, 3>(3, 0);
  p.dv_db_g = m.J_bias.block<3, 3>(6, 0);
  p.C_integral = -m.J_bias.block<3, 3>(6, 3);
  p.bg_ref = m.bg_hat;
  p.ba_ref = m.ba_hat;
  p.P_delta = m.cov;
  kernels::Okvis2Information(m.cov, p.information);
  return p;
}

struct Okvis2Factor {
  static constexpr const char* kIncrementConvention = "okvis2";
  static constexpr const char* kLayout =
      "OKVIS2 ImuError::EvaluateWithMinimalJacobians, raw (before weighting): residual "
      "[p, 2 vec(Dq (x) q_1^-1 (x) q_0), v, bg_0 - bg_1, ba_0 - ba_1] with Dq = "
      "exp(-dalpha_db_g dbg) (x) Delta_q and dbg, dba from the measurement's bias to x_s's "
      "(first order); jacobian_pose_0/1 15x7 w.r.t. [x y z qx qy qz qw], "
      "jacobian_speedbias_0/1 15x9 w.r.t. [v, bg, ba]; jacobian_pose_0/1_minimal 15x6 w.r.t. "
      "PoseManifold::plus (r + dr, C = Exp(dalpha) C, world frame); information = OKVIS's "
      "pseudo-inverse of P_delta (the weighting is a square root of it, whose row signs an "
      "eigen-solver chooses: not written); state_0 = x_s (q_0 with w >= 0), state_1 = x_e "
      "(q_1's sign making the rotation error's w >= 0); the measurement expressed in okvis2, "
      "gravity (0, 0, -g)";
  static constexpr int kDegreesOfFreedom = 15;
  // As a cost (residual_cost_spec.h): the raw residual whitened by a square root of the
  // information (OKVIS's own has eigen-solver row signs; the cost does not depend on which
  // root). The minimal pose Jacobians (r + dr, Exp(dalpha) C) and the additive speed-and-bias
  // ones are in the chart of the `okvis2` state convention, [r, alpha | v, bg, ba].
  static constexpr ResidualCostSpec kCostSpec =
      plugin::CostSpecOf("raw/residual", "okvis2", ResidualWeighting::Information, "information",
                         {{"raw/jacobian_pose_0_minimal", Block::p, Block::theta},
                          {"raw/jacobian_speedbias_0", Block::v, Block::bg, Block::ba}},
                         {{"raw/jacobian_pose_1_minimal", Block::p, Block::theta},
                          {"raw/jacobian_speedbias_1", Block::v, Block::bg, Block::ba}});

  Status operator()(const Preintegrated& m, const ImuState& x_s, const ImuState& x_e,
                    const Vec3& gravity, ResidualSink& sink) const {
    if (gravity.x() != 0.0 || gravity.y() != 0.0)
      return Status::Error(
          "okvis2: OKVIS2's gravity is (0, 0, -g) in its world frame; this gravity has x or y "
          "components");
    kernels::Okvis2ImuParameters params;
    params.g = -gravity.z();
    const kernels::Okvis2Preintegration pre = Okvis2PreintegrationOf(m);
    kernels::Okvis2State s0 = kernels::Okvis2StateOf(x_s), s1 = kernels::Okvis2StateOf(x_e);
    // A state here is a rotation matrix, a quaternion only up to sign; OKVIS's Jacobians
    // w.r.t. the quaternion's coefficients and its rotation residual 2 vec(Dq q_1^-1 q_0)
    // change sign with it. q_0 is taken with w >= 0 and q_1 so that the rotation error is
    // near +1, as it is when q_1 comes from propagating q_0.
    if (s0.q.w() < 0.0) s0.q.coeffs() = -s0.q.coeffs();
    const Eigen::Quaterniond Dq = pre.Delta_q;
    if ((Dq * (s1.q.inverse() * s0.q)).w() < 0.0) s1.q.coeffs() = -s1.q.coeffs();
    const kernels::Okvis2ImuErrorTerms t =
        kernels::EvaluateOkvis2ImuError(pre, params, m.dt, s0, s1);
    sink.begin_group("raw");
    WriteVector(sink, "residual", t.residual);
    WriteMatrix(sink, "jacobian_pose_0", t.jacobian_pose_0);
    WriteMatrix(sink, "jacobian_speedbias_0", t.jacobian_speedbias_0);
    WriteMatrix(sink, "jacobian_pose_1", t.jacobian_pose_1);
    WriteMatrix(sink, "jacobian_speedbias_1", t.jacobian_speedbias_1);
    WriteMatrix(sink, "jacobian_pose_0_minimal", t.jacobian_pose_0_minimal);
    WriteMatrix(sink, "jacobian_pose_1_minimal", t.jacobian_pose_1_minimal);
    sink.end_group();
    WriteMatrix(sink, "information", pre.information);
    sink.mahalanobis_squared(t.residual.dot(pre.information * t.residual));
    return Status::Ok();
  }
};

}  // namespace

IMUCONV_PLUGIN(Residual, imuconv::plugin::KernelResidual<Okvis2Factor>, "okvis2", "1.0.0",
               "OKVIS2 ImuError: raw residual, 15x7/15x9 and minimal Jacobians, information "
               "(P_delta's pseudo-inverse)")
