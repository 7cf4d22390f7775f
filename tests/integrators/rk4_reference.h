// An independent reference for the rk4 kernel: the classical RK4 of the state (Lie-group,
// Munthe-Kaas), of the transition Phi and of the covariance, dPhi/dt = F Phi and
// dP/dt = F P + P F^T + G Q G^T, all on the same four stages. It is the kernel as it was before
// the variation-of-constants covariance (git 0599b98), rewritten so that it shares no code with
// the kernels (core/include/imuconv/kernels/, core/src/kernels/): only SO(3), the value types and
// the left chart's block offsets. In particular the noise is squared here, from the densities
// (ProcessNoiseDiagonal), not by the kernels' NoiseVariances: a wrong factor there must show as
// a difference to this reference (rk4_noise.cpp; tests/mutations/ keeps that mutation).
// It is fourth order in all three but costs ~3600 flops per sample on the covariance; the
// kernel and this reference must agree to their O(dt^4) discretisation error
// (rk4_cross_check.cpp).
#pragma once

#include <cstddef>

#include "imuconv/propagator.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"
#include "imuconv/types.h"
#include "imuconv/window.h"

namespace imuconv::test::rk4_reference {

namespace rk4_detail {

/// The diagonal of G Q G^T in the left chart [p, theta, v, bg, ba], from the four continuous
/// noise densities. The note's continuous error model (eq. cont-error) is
/// d dx/dt = F dx + G n with n ~ N(0, Q delta(t)); Q is the diagonal of the densities squared,
/// sigma_g^2 (rad^2/s), sigma_a^2 (m^2/s^3), sigma_bg^2 (rad^2/s^3), sigma_ba^2 (m^2/s^5) on
/// three axes each. G maps the gyro noise to -R n_g on theta and the accelerometer noise to
/// -R n_a on v (the noise enters where the bias does, d dtheta/dt = -R dbg); the random walks
/// enter the biases unchanged and nothing enters p. Since R R^T = I, G Q G^T is diagonal:
/// sigma_g^2 on theta, sigma_a^2 on v, sigma_bg^2 on bg, sigma_ba^2 on ba, 0 on p. (The
/// discrete noise of a step dt would be Q/dt, the note's w_k; this reference integrates the
/// continuous Lyapunov equation, so it takes Q itself.)
inline Vec15 ProcessNoiseDiagonal(const ImuNoise& n) {
  using namespace left_idx;
  Vec15 d = Vec15::Zero();
  d.segment<3>(theta).setConstant(n.gyro_noise_density * n.gyro_noise_density);
  d.segment<3>(v).setConstant(n.accel_noise_density * n.accel_noise_density);
  d.segment<3>(bg).setConstant(n.gyro_random_walk * n.gyro_random_walk);
  d.segment<3>(ba).setConstant(n.accel_random_walk * n.accel_random_walk);
  return d;
}

/// F M for the left chart's error dynamics (reference_charts.h, the note's eq. left-dpr..
/// left-dba): d dp/dt = dv, d dtheta/dt = -R dbg, d dv/dt = -[R a]x dtheta - R dba,
/// d db/dt = 0. F is zero outside the p, theta and v rows, so F M is those three block rows.
inline Mat15 ErrorRateTimes(const Mat3& R, const Vec3& Ra, const Mat15& M) {
  using namespace left_idx;
  Mat15 FM = Mat15::Zero();
  FM.middleRows<3>(p) = M.middleRows<3>(v);
  FM.middleRows<3>(theta) = -R * M.middleRows<3>(bg);
  FM.middleRows<3>(v) = -so3::skew(Ra) * M.middleRows<3>(theta) - R * M.middleRows<3>(ba);
  return FM;
}

/// dP/dt = F P + P F^T + D for a symmetric P (P F^T = (F P)^T).
inline Mat15 CovarianceRate(const Mat3& R, const Vec3& Ra, const Mat15& P,
                            const Vec15& noise_diag) {
  const Mat15 FP = ErrorRateTimes(R, Ra, P);
  Mat15 rate = FP + FP.transpose();
  rate.diagonal() += noise_diag;
  return rate;
}

}  // namespace rk4_detail

/// Input of one RK4 step at its start, middle and end, biases already removed.
struct Rk4StepInput {
  Vec3 w0, wm, w1;  ///< body rate
  Vec3 a0, am, a1;  ///< specific force
};

/// One classical RK4 step of length h of the state, of Phi and of the covariance P (biases are
/// constant along the nominal trajectory).
inline void Rk4Step(ImuState& x, Mat15& Phi, Mat15& P, const Rk4StepInput& u, double h,
                    const Vec3& gravity, const Vec15& noise_diag) {
  using namespace rk4_detail;
  const double half_h = 0.5 * h;

  // Stage c = 0, 1/2, 1/2, 1. The rotation of stage i is R_0 Exp(phi_i) with
  // phi_i = c_i h k_{i-1}^phi, and k^phi = Jr^{-1}(phi) w is the rate of phi.
  Mat3 R[4];
  Vec3 Ra[4];
  Vec3 k_phi[4], k_v[4], v_stage[4];
  R[0] = x.R;
  k_phi[0] = u.w0;  // Jr^{-1}(0) = I
  v_stage[0] = x.v;
  Ra[0] = R[0] * u.a0;
  k_v[0] = gravity + Ra[0];
  for (int i = 1; i < 4; ++i) {
    const double c_h = i < 3 ? half_h : h;
    const Vec3 phi = c_h * k_phi[i - 1];
    R[i] = x.R * so3::Exp(phi);
    const Vec3& w = i < 3 ? u.wm : u.w1;
    const Vec3& a = i < 3 ? u.am : u.a1;
    k_phi[i] = so3::JrInv(phi) * w;
    v_stage[i] = x.v + c_h * k_v[i - 1];
    Ra[i] = R[i] * a;
    k_v[i] = gravity + Ra[i];
  }
  const double h6 = h / 6.0;
  const double weight[4] = {1.0, 2.0, 2.0, 1.0};

  // Phi and P as two more RK4 systems driven by the same stage states:
  // Y_i = Y + c_i h K_{i-1}, K_i = rate(stage i, Y_i), Y += h/6 sum weight_i K_i.
  Mat15 K_phi = ErrorRateTimes(R[0], Ra[0], Phi), K_P = CovarianceRate(R[0], Ra[0], P, noise_diag);
  Mat15 sum_phi = K_phi, sum_P = K_P;
  for (int i = 1; i < 4; ++i) {
    const double c_h = i < 3 ? half_h : h;
    const Mat15 Phi_stage = Phi + c_h * K_phi, P_stage = P + c_h * K_P;
    K_phi = ErrorRateTimes(R[i], Ra[i], Phi_stage);
    K_P = CovarianceRate(R[i], Ra[i], P_stage, noise_diag);
    sum_phi += weight[i] * K_phi;
    sum_P += weight[i] * K_P;
  }
  Phi += h6 * sum_phi;
  P += h6 * sum_P;

  // The state last: the stages above read x.R and x.v at the start of the step.
  const Vec3 phi = h6 * (k_phi[0] + 2.0 * (k_phi[1] + k_phi[2]) + k_phi[3]);
  x.p += h6 * (v_stage[0] + 2.0 * (v_stage[1] + v_stage[2]) + v_stage[3]);
  x.v += h6 * (k_v[0] + 2.0 * (k_v[1] + k_v[2]) + k_v[3]);
  x.R = x.R * so3::Exp(phi);
}

/// Integrates over the whole window with `substeps` RK4 steps per knot interval (inputs
/// interpolated linearly within it), without checking the input. Fills out.x_e, out.Phi and
/// out.cov.
inline void IntegrateRk4(const PropagationInput& in, PropagationResult& out, int substeps = 1) {
  const SampleWindow& w = in.window;
  const Vec15 noise_diag = rk4_detail::ProcessNoiseDiagonal(in.noise);
  ImuState x = in.x_s;
  Mat15 Phi = Mat15::Identity();
  Mat15 P = in.cov_s;
  const std::size_t intervals = w.size() - 1;
  const double inv_n = 1.0 / substeps;
  const ImuSample* k0 = &w[0];
  Rk4StepInput u;
  for (std::size_t k = 0; k < intervals; ++k) {
    const ImuSample* k1 = &w[k + 1];
    const double dt = k1->t - k0->t;
    const Vec3 w_k0 = k0->gyro - x.bg, a_k0 = k0->accel - x.ba;
    const Vec3 w_k1 = k1->gyro - x.bg, a_k1 = k1->accel - x.ba;
    const Vec3 dw = w_k1 - w_k0, da = a_k1 - a_k0;
    const double h = dt * inv_n;
    u.w1 = w_k0, u.a1 = a_k0;
    for (int i = 0; i < substeps; ++i) {
      // Linear interpolation at the substep's start, middle and end (fractions of dt).
      const double s_mid = (i + 0.5) * inv_n, s_end = (i + 1) * inv_n;
      u.w0 = u.w1, u.a0 = u.a1;
      u.wm = w_k0 + s_mid * dw, u.am = a_k0 + s_mid * da;
      u.w1 = i + 1 == substeps ? w_k1 : Vec3(w_k0 + s_end * dw);
      u.a1 = i + 1 == substeps ? a_k1 : Vec3(a_k0 + s_end * da);
      Rk4Step(x, Phi, P, u, h, in.gravity, noise_diag);
    }
    k0 = k1;
  }
  out.x_e = x;
  out.Phi = Phi;
  out.cov = 0.5 * (P + P.transpose());
}

}  // namespace imuconv::test::rk4_reference
