// Basalt's IMU residual (basalt-headers, IntegratedImuMeasurement::residual), reproduced to
// round-off on a Basalt delta state (kernels/basalt.h): the 9-vector [trans, rot, vel], its
// Jacobians w.r.t. the two states' applyInc increments and w.r.t. the two biases.
//
// With T the measurement's dt_ns 1e-9, (R0, p0, v0) and (R1, p1, v1) the two states
// (body-to-world), g the gravity vector, D = [Dp, DR, Dv] the delta state, J_ba and J_bg its
// 9x3 bias Jacobians (rows [p, theta, v]) and db the bias minus its linearization value:
//   b_g = J_bg dbg, b_a = J_ba dba                  (the first-order corrections, 9-vectors)
//   r_p     = R0^T (p1 - p0 - v0 T - g T^2/2) - (Dp + b_g,p + b_a,p)
//   r_theta = Log(Exp(b_g,theta) DR R1^T R0)
//   r_v     = R0^T (v1 - v0 - g T) - (Dv + b_g,v + b_a,v)
// (the accelerometer bias does not move the rotation: J_ba's theta rows are zero).
//
// Increments (PoseVelState::applyInc): p += dp, R = Exp(dtheta) R (left, world frame),
// v += dv; order [trans, rot, vel]. The Jacobians:
//   d r / d state0 = [-R0^T  [a]x R0^T  -R0^T T; 0  Jr^-1(r_theta) R0^T  0; 0  [b]x R0^T  -R0^T]
//   d r / d state1 = [ R0^T  0  0;  0  -Jr^-1(r_theta) R0^T  0;  0  0  R0^T]
//     with a = R0^T (p1 - p0 - v0 T - g T^2/2), b = R0^T (v1 - v0 - g T);
//   d r / d ba = -J_ba;  d r / d bg = -J_bg with its theta rows Jl^-1(r_theta) J_bg,theta.
// All are exact derivatives at the linearization bias. Away from it upstream's theta rows
// of d r / d bg omit the factor Jl(b_g,theta) of the derivative of Exp(b_g,theta) (an error
// of order |b_g,theta|/2 relative), kept here as upstream has it.
#pragma once

#include "imuconv/export.h"
#include "imuconv/kernels/basalt.h"
#include "imuconv/types.h"

namespace imuconv::kernels {

using Mat93 = Eigen::Matrix<double, 9, 3>;

/// A PoseVelState: body-to-world rotation, position and velocity in the world.
struct BasaltPoseVelState {
  Mat3 R = Mat3::Identity();
  Vec3 p = Vec3::Zero(), v = Vec3::Zero();
};

/// An IntegratedImuMeasurement: the delta state with its linearization biases.
struct BasaltMeasurement {
  BasaltPreintegration pre;
  Vec3 bias_gyro_lin = Vec3::Zero(), bias_accel_lin = Vec3::Zero();
};

/// residual()'s outputs.
struct BasaltResidual {
  Vec9 residual = Vec9::Zero();
  Mat9 d_res_d_state0 = Mat9::Zero(), d_res_d_state1 = Mat9::Zero();
  Mat93 d_res_d_bg = Mat93::Zero(), d_res_d_ba = Mat93::Zero();
};

/// The first-order bias-corrected delta state residual() compares against (header).
IMUCONV_API BasaltPoseVelState BasaltCorrectedDelta(const BasaltMeasurement& m, const Vec3& bg,
                                                    const Vec3& ba);

/// IntegratedImuMeasurement::residual(state0, g, state1, curr_bg, curr_ba) with its Jacobians.
IMUCONV_API BasaltResidual BasaltResidualOf(const BasaltMeasurement& m,
                                            const BasaltPoseVelState& state0, const Vec3& g,
                                            const BasaltPoseVelState& state1, const Vec3& curr_bg,
                                            const Vec3& curr_ba);

/// PoseVelState::applyInc: [trans, rot (left, world), vel].
IMUCONV_API BasaltPoseVelState BasaltApplyInc(const BasaltPoseVelState& x, const Vec9& inc);

}  // namespace imuconv::kernels
