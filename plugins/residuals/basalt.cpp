// `basalt`: Basalt's IntegratedImuMeasurement::residual (VladyslavUsenko/basalt-headers,
// imu/preintegration.h) as a residual plugin: the 9-dim residual [trans, rot, vel] between two
// PoseVelStates with its Jacobians w.r.t. their increments (PoseVelState::applyInc) and the
// two biases, in Basalt's own layout; weighted by the measurement's 9x9 covariance, as
// Basalt's optimizer does (get_cov_inv). The kernel is
// core/include/imuconv/kernels/basalt_residual.h; it agrees with Basalt's own numbers on the
// ten reference cases (tests/reference/basalt_residual_anchor.cpp).
#include <Eigen/Cholesky>
#include <cmath>

#include "imuconv/kernels/basalt_residual.h"
#include "imuconv/plugin/residual_plugin.h"
#include "imuconv/plugin_abi.h"
#include "jacobian_blocks.h"

namespace {

using namespace imuconv;

/// Basalt's IntegratedImuMeasurement from a measurement expressed in `basalt` (J_bias rows
/// [p, theta, v], columns [bg, ba]); its time in Basalt's integer nanoseconds.
kernels::BasaltMeasurement BasaltMeasurementOf(const Preintegrated& m) {
  kernels::BasaltMeasurement b;
  b.pre.dt_ns = std::llround(m.dt * 1e9);
  b.pre.R = m.delta.dR;
  b.pre.p = m.delta.dp;
  b.pre.v = m.delta.dv;
  b.pre.cov = m.cov.topLeftCorner<9, 9>();
  b.pre.d_state_d_bg = m.J_bias.leftCols<3>();
  b.pre.d_state_d_ba = m.J_bias.rightCols<3>();
  b.bias_gyro_lin = m.bg_hat;
  b.bias_accel_lin = m.ba_hat;
  return b;
}

constexpr auto* BasaltState = &plugin::PoseVelOf<kernels::BasaltPoseVelState>;

struct BasaltFactor {
  static constexpr const char* kIncrementConvention = "basalt";
  static constexpr const char* kLayout =
      "Basalt IntegratedImuMeasurement::residual: residual [trans, rot, vel]; d_res_d_state0/1 "
      "9x9 w.r.t. "
      "PoseVelState::applyInc (p + dp, Exp(dtheta) R, v + dv); d_res_d_bg, d_res_d_ba 9x3; "
      "state0 = x_s "
      "with curr_bg/ba = x_s's biases, state1 = x_e; the measurement expressed in basalt";
  static constexpr int kDegreesOfFreedom = 9;
  // As a cost (residual_cost_spec.h): 9 rows, no bias-walk rows (Basalt weights the bias
  // random walk in a separate term), whitened by a square root of the measurement's
  // covariance inverse (get_cov_inv). applyInc moves p + dp, Exp(dtheta) R, v + dv and the
  // biases additively: the chart of `left`; the end state's biases do not enter.
  static constexpr ResidualCostSpec kCostSpec =
      plugin::CostSpecOf("residual", "left", ResidualWeighting::MeasurementCovariance, nullptr,
                         {{"d_res_d_state0", Block::p, Block::theta, Block::v},
                          {"d_res_d_bg", Block::bg},
                          {"d_res_d_ba", Block::ba}},
                         {{"d_res_d_state1", Block::p, Block::theta, Block::v}});

  Status operator()(const Preintegrated& m, const ImuState& x_s, const ImuState& x_e,
                    const Vec3& gravity, ResidualSink& sink) const {
    if (!std::isfinite(m.dt) || !(std::abs(m.dt) < 9e9))
      return Status::Error("basalt: the measurement's dt " + std::to_string(m.dt) +
                           " s does not fit Basalt's integer nanoseconds");
    const kernels::BasaltMeasurement b = BasaltMeasurementOf(m);
    const kernels::BasaltResidual res =
        kernels::BasaltResidualOf(b, BasaltState(x_s), gravity, BasaltState(x_e), x_s.bg, x_s.ba);
    WriteVector(sink, "residual", res.residual);
    WriteMatrix(sink, "d_res_d_state0", res.d_res_d_state0);
    WriteMatrix(sink, "d_res_d_state1", res.d_res_d_state1);
    WriteMatrix(sink, "d_res_d_bg", res.d_res_d_bg);
    WriteMatrix(sink, "d_res_d_ba", res.d_res_d_ba);
    // r^T cov^-1 r, when the covariance is positive definite (a measurement without noise
    // has no weighting: then no distance).
    const Eigen::LDLT<Mat9> ldlt(b.pre.cov);
    if (ldlt.info() == Eigen::Success && ldlt.isPositive() && ldlt.vectorD().minCoeff() > 0.0)
      sink.mahalanobis_squared(res.residual.dot(ldlt.solve(res.residual)));
    return Status::Ok();
  }
};

}  // namespace

IMUCONV_PLUGIN(Residual, imuconv::plugin::KernelResidual<BasaltFactor>, "basalt", "1.0.0",
               "Basalt IntegratedImuMeasurement::residual: 9-dim [trans, rot, vel], Jacobians "
               "w.r.t. applyInc and the biases")
