// `vins_fusion`: VINS-Fusion's IMUFactor::Evaluate (HKUST-Aerial-Robotics/VINS-Fusion,
// vins_estimator/src/factor/imu_factor.h) as a residual plugin: the raw factor (sqrt_info =
// I), IMUFactor's square-root information LLT(cov^-1).L^T and the whitened factor, in VINS's
// own layout (15-dim residual [p, theta, v, ba, bg], 15x7 pose Jacobians with a zero q.w
// column, 15x9 speed-and-bias Jacobians). The kernel is
// core/include/imuconv/kernels/vins_fusion_residual.h; it agrees with VINS-Fusion's own numbers
// on the ten reference cases (tests/reference/vins_fusion_residual_anchor.cpp).
#include <Eigen/Geometry>

#include "imuconv/kernels/system_state.h"
#include "imuconv/kernels/vins_fusion_residual.h"
#include "imuconv/plugin/residual_plugin.h"
#include "imuconv/plugin_abi.h"
#include "jacobian_blocks.h"

namespace {

using namespace imuconv;

/// VINS-Fusion's IntegrationBase from a measurement expressed in `vins_fusion` (the bias
/// columns of its Jacobian product are the convention's J_bias, rows [p, theta, v], columns
/// [ba, bg]; the rest of the product is not used by the factor).
kernels::VinsFusionMeasurement VinsMeasurement(const Preintegrated& m, const Vec3& gravity) {
  kernels::VinsFusionMeasurement v;
  v.pre.sum_dt = m.dt;
  v.pre.delta_p = m.delta.dp;
  v.pre.delta_v = m.delta.dv;
  v.pre.delta_q = Eigen::Quaterniond(m.delta.dR);
  v.pre.jacobian.setIdentity();
  v.pre.jacobian.block<9, 6>(0, 9) = m.J_bias;
  v.pre.covariance = m.cov;
  v.linearized_ba = m.ba_hat;
  v.linearized_bg = m.bg_hat;
  v.G = -gravity;
  return v;
}

kernels::VinsFusionFactorState VinsState(const ImuState& x) {
  using S = kernels::VinsFusionFactorState;
  return kernels::SystemStateOf(x, &S::P, &S::Q, &S::V, &S::Bg, &S::Ba);
}

void WriteFactorOutput(ResidualSink& sink, const char* group,
                       const kernels::VinsFusionFactorOutput& o) {
  sink.begin_group(group);
  WriteVector(sink, "residual", o.residual);
  WriteMatrix(sink, "jacobian_pose_i", o.jacobian_pose_i);
  WriteMatrix(sink, "jacobian_speedbias_i", o.jacobian_speedbias_i);
  WriteMatrix(sink, "jacobian_pose_j", o.jacobian_pose_j);
  WriteMatrix(sink, "jacobian_speedbias_j", o.jacobian_speedbias_j);
  sink.end_group();
}

struct VinsFusionFactor {
  static constexpr const char* kIncrementConvention = "vins_fusion";
  static constexpr const char* kLayout =
      "VINS-Fusion IMUFactor::Evaluate: residual [p, theta, v, ba, bg] "
      "(IntegrationBase::evaluate); "
      "jacobian_pose_i/j 15x7 w.r.t. PoseLocalParameterization (p + dp, q (x) [1, dtheta/2] "
      "normalized), "
      "columns [dp, dtheta, 0]; jacobian_speedbias_i/j 15x9, columns [v, ba, bg]; raw "
      "(sqrt_info = I) and "
      "whitened by sqrt_info = LLT(cov^-1).L^T; state i = x_s (its biases the current "
      "estimate), j = x_e; "
      "the measurement expressed in vins_fusion, G = -gravity";
  static constexpr int kDegreesOfFreedom = 15;
  // As a cost (residual_cost_spec.h): the raw residual whitened by IMUFactor's own sqrt_info.
  // PoseLocalParameterization moves a pose by p + dp (world) and q (x) [1, dtheta/2]
  // normalized, which is R Exp(dtheta) to first order, and the speed-bias block additively:
  // to first order the chart of `fast_lio2` (pos + dp, R Exp(drot), vel + dv, b + db), whose
  // blocks VINS's columns hold in its order [p, theta | v, ba, bg].
  static constexpr ResidualCostSpec kCostSpec = plugin::CostSpecOf(
      "raw/residual", "fast_lio2", ResidualWeighting::SqrtInformation, "sqrt_info",
      {{"raw/jacobian_pose_i", Block::p, Block::theta},
       {"raw/jacobian_speedbias_i", Block::v, Block::ba, Block::bg}},
      {{"raw/jacobian_pose_j", Block::p, Block::theta},
       {"raw/jacobian_speedbias_j", Block::v, Block::ba, Block::bg}});

  Status operator()(const Preintegrated& m, const ImuState& x_s, const ImuState& x_e,
                    const Vec3& gravity, ResidualSink& sink) const {
    const kernels::VinsFusionMeasurement v = VinsMeasurement(m, gravity);
    const kernels::VinsFusionFactorState i = VinsState(x_s);
    kernels::VinsFusionFactorState j = VinsState(x_e);
    // A state here is a rotation matrix, a quaternion only up to sign, and VINS's rotation
    // residual 2 vec(c_q^-1 Q_i^-1 Q_j) changes sign with Q_j. In VINS-Fusion Q_j comes from
    // Q_i delta_q, so that error quaternion is near +1; Q_j's sign is chosen to make it so.
    const Eigen::Quaterniond c_q = kernels::VinsFusionCorrect(v, i.Ba, i.Bg).delta_q;
    if ((c_q.inverse() * (i.Q.inverse() * j.Q)).w() < 0.0) j.Q.coeffs() = -j.Q.coeffs();
    const kernels::VinsFusionFactorOutput raw = kernels::VinsFusionRawFactor(v, i, j);
    WriteFactorOutput(sink, "raw", raw);
    // IMUFactor's whitening, when the covariance allows it (a measurement without noise,
    // e.g. from zero densities, has none: then only the raw factor is written).
    Mat15 sqrt_info;
    if (kernels::VinsFusionSqrtInfo(v.pre.covariance, sqrt_info).ok()) {
      const kernels::VinsFusionFactorOutput white = kernels::VinsFusionWhiten(raw, sqrt_info);
      WriteMatrix(sink, "sqrt_info", sqrt_info);
      WriteFactorOutput(sink, "whitened", white);
      sink.mahalanobis_squared(white.residual.squaredNorm());
    }
    return Status::Ok();
  }
};

}  // namespace

IMUCONV_PLUGIN(Residual, imuconv::plugin::KernelResidual<VinsFusionFactor>, "vins_fusion", "1.0.0",
               "VINS-Fusion IMUFactor::Evaluate: raw, sqrt_info and whitened, 15x7 pose and 15x9 "
               "speed-bias Jacobians")
