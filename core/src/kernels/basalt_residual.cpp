// Basalt's IMU residual (see imuconv/kernels/basalt_residual.h for the formulas). Rotation
// matrices stand where upstream uses Sophus's unit quaternions: the same maps, rounded in
// another order.
#include "imuconv/kernels/basalt_residual.h"

#include "imuconv/so3.h"

namespace imuconv::kernels {

namespace {
constexpr int kP = 0, kTheta = 3, kV = 6;
}  // namespace

BasaltPoseVelState BasaltCorrectedDelta(const BasaltMeasurement& m, const Vec3& bg,
                                        const Vec3& ba) {
  const Vec9 bg_diff = m.pre.d_state_d_bg * (bg - m.bias_gyro_lin);
  const Vec9 ba_diff = m.pre.d_state_d_ba * (ba - m.bias_accel_lin);
  BasaltPoseVelState c;
  c.p = m.pre.p + bg_diff.segment<3>(kP) + ba_diff.segment<3>(kP);
  c.R = so3::Exp(bg_diff.segment<3>(kTheta)) * m.pre.R;
  c.v = m.pre.v + bg_diff.segment<3>(kV) + ba_diff.segment<3>(kV);
  return c;
}

BasaltResidual BasaltResidualOf(const BasaltMeasurement& m, const BasaltPoseVelState& state0,
                                const Vec3& g, const BasaltPoseVelState& state1,
                                const Vec3& curr_bg, const Vec3& curr_ba) {
  const double T = static_cast<double>(m.pre.dt_ns) * 1e-9;
  const BasaltPoseVelState c = BasaltCorrectedDelta(m, curr_bg, curr_ba);
  const Mat3 R0_T = state0.R.transpose();
  const Vec3 a = R0_T * (state1.p - state0.p - state0.v * T - 0.5 * g * T * T);
  const Vec3 b = R0_T * (state1.v - state0.v - g * T);

  BasaltResidual out;
  out.residual.segment<3>(kP) = a - c.p;
  out.residual.segment<3>(kTheta) = so3::Log(c.R * state1.R.transpose() * state0.R);
  out.residual.segment<3>(kV) = b - c.v;
  const Vec3 r_theta = out.residual.segment<3>(kTheta);

  const Mat3 Jr_inv = so3::JrInv(r_theta);
  Mat9& J0 = out.d_res_d_state0;
  J0.block<3, 3>(kP, kP) = -R0_T;
  J0.block<3, 3>(kP, kTheta) = so3::skew(a) * R0_T;
  J0.block<3, 3>(kP, kV) = -R0_T * T;
  J0.block<3, 3>(kTheta, kTheta) = Jr_inv * R0_T;
  J0.block<3, 3>(kV, kTheta) = so3::skew(b) * R0_T;
  J0.block<3, 3>(kV, kV) = -R0_T;
  Mat9& J1 = out.d_res_d_state1;
  J1.block<3, 3>(kP, kP) = R0_T;
  J1.block<3, 3>(kTheta, kTheta) = -Jr_inv * R0_T;
  J1.block<3, 3>(kV, kV) = R0_T;

  out.d_res_d_ba = -m.pre.d_state_d_ba;
  out.d_res_d_bg = -m.pre.d_state_d_bg;
  // Upstream's theta rows: Jl^-1(r_theta) J_bg,theta (without Jl of the correction, header).
  out.d_res_d_bg.middleRows<3>(kTheta) =
      so3::JlInv(r_theta) * m.pre.d_state_d_bg.middleRows<3>(kTheta);
  return out;
}

BasaltPoseVelState BasaltApplyInc(const BasaltPoseVelState& x, const Vec9& inc) {
  BasaltPoseVelState y = x;
  y.p += inc.segment<3>(kP);
  y.R = so3::Exp(inc.segment<3>(kTheta)) * x.R;
  y.v += inc.segment<3>(kV);
  return y;
}

}  // namespace imuconv::kernels
