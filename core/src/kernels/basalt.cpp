// Basalt's preintegration (see imuconv/kernels/basalt.h for the step, its error state, the
// two feedings and the noise). F is applied from its two nonzero off-identity blocks; A and G
// are 9x3 and their noise terms formed directly.
#include "imuconv/kernels/basalt.h"

#include <cmath>

#include "imuconv/kernels/preintegration.h"
#include "imuconv/so3.h"

namespace imuconv::kernels {

namespace {

using Mat93 = Eigen::Matrix<double, 9, 3>;
constexpr int kP = 0, kTheta = 3, kV = 6;

/// out = F M for F = [I F_pt I dt; 0 I 0; 0 F_vt I] and any M with 9 rows.
template <int Cols>
void ApplyStep(const Mat3& F_pt, const Mat3& F_vt, double dt,
               const Eigen::Matrix<double, 9, Cols>& M, Eigen::Matrix<double, 9, Cols>& out) {
  const auto p = M.template middleRows<3>(kP), t = M.template middleRows<3>(kTheta),
             v = M.template middleRows<3>(kV);
  out.template middleRows<3>(kP) = p + F_pt * t + dt * v;
  out.template middleRows<3>(kTheta) = t;
  out.template middleRows<3>(kV) = F_vt * t + v;
}

/// Basalt's timestamps: integer nanoseconds.
long long Nanoseconds(double t) { return std::llround(t * 1e9); }

}  // namespace

Status IntegrateBasalt(const PreintegrationInput& in, BasaltFeeding feeding,
                       const std::optional<BasaltSampleVariances>& variances,
                       BasaltPreintegration& out, bool jacobians) {
  if (Status s = CheckPreintegrationInput(in); !s.ok()) return s;
  const SampleWindow& w = in.window;
  out = BasaltPreintegration{};
  const ImuNoise& n = in.noise;
  Mat9 FM, FMt;
  Mat93 A = Mat93::Zero(), G = Mat93::Zero(), FJ;
  long long t_prev = Nanoseconds(w[0].t);
  for (std::size_t j = 0; j + 1 < w.size(); ++j) {
    const long long t_next = Nanoseconds(w[j + 1].t);
    if (t_next <= t_prev)
      return Status::Error("knots " + std::to_string(j) + " and " + std::to_string(j + 1) +
                           " are less than 1 ns apart (Basalt's time unit)");
    const long long step_ns = t_next - t_prev;
    const double dt = static_cast<double>(step_ns) * 1e-9;
    t_prev = t_next;
    const ImuSample& held = feeding == BasaltFeeding::kNative ? w[j + 1] : w[j];
    const Vec3 a = held.accel - in.ba, omega = held.gyro - in.bg;

    const Mat3 R_half = out.R * so3::Exp((0.5 * dt) * omega);
    const Vec3 a_w = R_half * a;
    const Mat3 R_next = out.R * so3::Exp(dt * omega);
    if (jacobians) {
      const Mat3 F_vt = so3::skew(-dt * a_w), F_pt = (0.5 * dt) * F_vt;

      A.middleRows<3>(kP) = (0.5 * dt * dt) * R_half;
      A.middleRows<3>(kV) = dt * R_half;
      G.middleRows<3>(kTheta) = R_next * so3::Jr(dt * omega) * dt;
      G.middleRows<3>(kV) = F_vt * R_half * so3::Jr((0.5 * dt) * omega) * (0.5 * dt);
      G.middleRows<3>(kP) = (0.5 * dt) * G.middleRows<3>(kV);

      const Vec3 accel_var =
          variances ? variances->accel
                    : Vec3::Constant(n.accel_noise_density * n.accel_noise_density / dt);
      const Vec3 gyro_var = variances
                                ? variances->gyro
                                : Vec3::Constant(n.gyro_noise_density * n.gyro_noise_density / dt);
      // cov' = F cov F^T = (F (F cov)^T)^T, cov symmetric.
      ApplyStep<9>(F_pt, F_vt, dt, out.cov, FM);
      ApplyStep<9>(F_pt, F_vt, dt, FM.transpose(), FMt);
      out.cov = FMt.transpose() + A * accel_var.asDiagonal() * A.transpose() +
                G * gyro_var.asDiagonal() * G.transpose();
      ApplyStep<3>(F_pt, F_vt, dt, out.d_state_d_ba, FJ);
      out.d_state_d_ba = FJ - A;
      ApplyStep<3>(F_pt, F_vt, dt, out.d_state_d_bg, FJ);
      out.d_state_d_bg = FJ - G;
    }

    out.p += out.v * dt + (0.5 * dt * dt) * a_w;
    out.v += dt * a_w;
    out.R = R_next;
    out.dt_ns += step_ns;
  }
  return Status::Ok();
}

Status IntegrateBasalt(const PreintegrationInput& in, BasaltFeeding feeding, Preintegrated& out,
                       BasaltNoiseMapping noise) {
  std::optional<BasaltSampleVariances> variances;
  if (noise == BasaltNoiseMapping::kAsConfigured) {
    variances.emplace();
    variances->gyro.setConstant(in.noise.gyro_noise_density * in.noise.gyro_noise_density);
    variances->accel.setConstant(in.noise.accel_noise_density * in.noise.accel_noise_density);
  }
  BasaltPreintegration r;
  if (Status s = IntegrateBasalt(in, feeding, variances, r); !s.ok()) return s;
  out.dt = static_cast<double>(r.dt_ns) * 1e-9;
  out.delta = PreintIncrement{};
  out.delta.dR = r.R;
  out.delta.dp = r.p;
  out.delta.dv = r.v;
  out.bg_hat = in.bg;
  out.ba_hat = in.ba;
  // [p, theta, v, bg, ba]: Basalt's 9x9, then the two walks over the interval.
  out.cov.setZero();
  out.cov.topLeftCorner<9, 9>() = r.cov;
  const ImuNoise& n = in.noise;
  out.cov.block<3, 3>(9, 9).diagonal().setConstant(n.gyro_random_walk * n.gyro_random_walk *
                                                   out.dt);
  out.cov.block<3, 3>(12, 12).diagonal().setConstant(n.accel_random_walk * n.accel_random_walk *
                                                     out.dt);
  out.J_bias << r.d_state_d_bg, r.d_state_d_ba;
  return Status::Ok();
}

}  // namespace imuconv::kernels
