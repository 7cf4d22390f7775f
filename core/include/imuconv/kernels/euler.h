// Euler (zero-order hold) and midpoint integration in the `left` error state, with the
// exact Jacobian of the discrete map as transition matrix and discrete noise.
//
// One step over [t_k, t_k+1], dt = t_k+1 - t_k, holds one gyro/accel value u = (w_m, a_m):
//   euler:    u = knot k                     (GTSAM fed (a_k, w_k, t_k+1 - t_k))
//   midpoint: u = (knot k + knot k+1) / 2    (OpenVINS' imu_avg; GTSAM's reference "mid")
// With w = w_m - bg and a = a_m - ba the step is the paper's eq. diff-state integrated with
// the rotation frozen at the start of the step for p and v, and exactly for R:
//   R' = R Exp(w dt),  v' = v + g dt + R a dt,  p' = p + v dt + g dt^2/2 + R a dt^2/2,
//   b' = b + w_b                               (bias random walk, w_b ~ N(0, sigma_b^2 dt I)).
// This is GTSAM's NavState::update followed by its prediction, so Phi and the covariance
// below reproduce ManifoldPreintegration after a change of chart; nothing is linearised
// beyond the exact first derivative of this map.
//
// Exact Jacobian of the step in the left chart (R = Exp(dtheta) R^, paper eq. left-dpr..):
//   dtheta' = dtheta - R' Jr(w dt) dt dbg             (Exp(w dt - dbg dt) ~ Exp(w dt) Exp(-Jr dbg
//   dt),
//                                                      moved to the left through R')
//   dv'     = dv - dt [R a]x dtheta - dt R dba        (Exp(dtheta) R a ~ R a - [R a]x dtheta)
//   dp'     = dp + dt dv - dt^2/2 [R a]x dtheta - dt^2/2 R dba
// Measurement noise n = (n_g, n_a) enters exactly where the biases do (w = w_m - bg - n_g,
// a = a_m - ba - n_a), as a discrete white sequence of covariance sigma^2/dt (paper,
// section 2.1, w_k ~ N(0, Q/dt)); so its Jacobians are the bias columns.
#pragma once

#include "imuconv/kernels/common.h"
#include "imuconv/kernels/left_transition.h"
#include "imuconv/kernels/preintegration.h"

namespace imuconv::kernels {

/// The free blocks of one Euler step's transition; the rest follows from them:
/// p_th = dt/2 v_th, p_ba = dt/2 v_ba, p_v = dt, v_bg = p_bg = 0.
struct EulerStepJacobian {
  Mat3 th_bg;  ///< d dtheta'/d dbg = d dtheta'/d n_g = -R' Jr(w dt) dt
  Mat3 v_th;   ///< d dv'/d dtheta = -dt [R a]x
  Mat3 v_ba;   ///< d dv'/d dba = d dv'/d n_a = -dt R
  double dt;

  LeftTransition ToTransition() const {
    LeftTransition T;
    T.th_bg = th_bg;
    T.v_th = v_th;
    T.v_ba = v_ba;
    T.p_th = 0.5 * dt * v_th;
    T.p_ba = 0.5 * dt * v_ba;
    T.p_v = dt;
    return T;
  }
};

/// One Euler step of the nominal state with a held input (the Basalt-style static step).
/// `next` may alias `x`. J is filled when kJacobian (it may be null otherwise).
template <bool kJacobian>
inline void EulerStep(const ImuState& x, const Vec3& gyro, const Vec3& accel, double dt,
                      const Vec3& gravity, ImuState& next, EulerStepJacobian* J) {
  const Vec3 w = gyro - x.bg;
  const Vec3 Ra = x.R * (accel - x.ba);
  const Vec3 acc_world = Ra + gravity;
  Mat3 dR, Jr;
  ExpAndJr(w * dt, dR, kJacobian ? &Jr : nullptr);
  if constexpr (kJacobian) {
    J->v_th = -dt * so3::skew(Ra);
    J->v_ba = -dt * x.R;
    J->dt = dt;
  }
  next.p = x.p + dt * x.v + (0.5 * dt * dt) * acc_world;  // before v: uses the old v
  next.v = x.v + dt * acc_world;
  next.R = x.R * dR;  // Eigen evaluates the product into a temporary, so aliasing is safe
  next.bg = x.bg;
  next.ba = x.ba;
  if constexpr (kJacobian) J->th_bg.noalias() = -dt * (next.R * Jr);
}

/// Phi <- step * Phi for an Euler step: LeftTransition::PrependStep with the step's zero and
/// proportional blocks folded in. The theta columns are left out: they follow from the state
/// at the end (see ThetaColumnsFromState), so only the bias columns are accumulated here.
inline void PrependEulerStepBiasColumns(const EulerStepJacobian& s, LeftTransition& Phi) {
  const double dt = s.dt, half_dt = 0.5 * s.dt;
  const Mat3 v_th_th_bg = s.v_th * Phi.th_bg;
  // p rows first: they read the v blocks before these are updated.
  Phi.p_bg += dt * Phi.v_bg + half_dt * v_th_th_bg;
  Phi.p_ba += dt * Phi.v_ba + half_dt * s.v_ba;
  Phi.v_bg += v_th_th_bg;
  Phi.v_ba += s.v_ba;
  Phi.th_bg += s.th_bg;
}

/// P <- A P A^T + B Q_d B^T + W for one Euler step, A = s.ToTransition().ToMatrix(),
/// Q_d = diag(sigma_g^2/dt I, sigma_a^2/dt I), W = diag(0, 0, 0, sigma_bg^2 dt I, sigma_ba^2 dt I).
///
/// With A = I + E, where E is non-zero only in the p, theta and v rows, and P symmetric:
///   A P A^T = P + C + C^T + E C,   C = P E^T,
/// and C is non-zero only in the p, theta and v columns. C is built from whole columns of P
/// (contiguous in Eigen's column-major storage), E C is 9x9, and the lower-left bias rows
/// are mirrored into the upper right instead of being computed twice.
inline void EulerCovarianceStep(const EulerStepJacobian& s, const NoiseVariances& q, Mat15& P) {
  using namespace left_idx;
  const double dt = s.dt, half_dt = 0.5 * s.dt;
  // E's rows: E_p = [0, dt/2 v_th, dt I, 0, dt/2 v_ba], E_theta = [0, 0, 0, th_bg, 0],
  // E_v = [0, v_th, 0, 0, v_ba]. C's columns are ordered p, theta, v like the state's.
  Eigen::Matrix<double, 15, 9> C;
  AssignTimes3x3(P.middleCols<3>(theta), s.v_th.transpose(), C.middleCols<3>(v));
  AddTimes3x3(P.middleCols<3>(ba), s.v_ba.transpose(), C.middleCols<3>(v));
  C.middleCols<3>(p) = dt * P.middleCols<3>(v) + half_dt * C.middleCols<3>(v);
  AssignTimes3x3(P.middleCols<3>(bg), s.th_bg.transpose(), C.middleCols<3>(theta));
  Eigen::Matrix<double, 9, 9> EC;
  EC.middleRows<3>(theta).noalias() = s.th_bg * C.middleRows<3>(bg);
  EC.middleRows<3>(v).noalias() = s.v_th * C.middleRows<3>(theta);
  EC.middleRows<3>(v).noalias() += s.v_ba * C.middleRows<3>(ba);
  EC.middleRows<3>(p) = dt * C.middleRows<3>(v) + half_dt * EC.middleRows<3>(v);

  P.leftCols<9>() += C;
  P.topLeftCorner<9, 9>() += C.topRows<9>().transpose() + EC;
  P.topRightCorner<9, 6>() = P.bottomLeftCorner<6, 9>().transpose();

  // Measurement noise through the bias columns. For n_a the columns are -dt^2/2 R (p) and
  // -dt R (v), so with R R^T = I its term is sigma_a^2/dt * dt^2 [dt^2/4, dt/2; dt/2, 1] (x) I.
  const double qa = q.accel * dt;
  P.block<3, 3>(theta, theta).noalias() += (q.gyro / dt) * (s.th_bg * s.th_bg.transpose());
  P.block<3, 3>(p, p).diagonal().array() += qa * half_dt * half_dt;
  P.block<3, 3>(p, v).diagonal().array() += qa * half_dt;
  P.block<3, 3>(v, p).diagonal().array() += qa * half_dt;
  P.block<3, 3>(v, v).diagonal().array() += qa;
  P.block<3, 3>(bg, bg).diagonal().array() += q.gyro_walk * dt;
  P.block<3, 3>(ba, ba).diagonal().array() += q.accel_walk * dt;
}

// Hold (how the value held over [t_k, t_k+1] is formed from the knots) is declared with the
// preintegration kernel, which runs both holds.

/// Integrates over the whole window one step at a time, without checking the input (see
/// PropagateHeld): the recursion above, in plain Eigen. Fills out.x_e, and out.Phi and
/// out.cov as `kOut` asks. It is the specification IntegrateHeldByPreintegration is
/// tested against (tests/integrators/routes.cpp).
template <Hold kHold, Outputs kOut = Outputs::All>
inline void IntegrateHeldPerSample(const PropagationInput& in, PropagationResult& out) {
  constexpr bool kPhi = WantsTransition(kOut), kCov = WantsCovariance(kOut);
  const SampleWindow& w = in.window;
  const NoiseVariances q(in.noise);
  ImuState x = in.x_s;
  LeftTransition Phi;
  Mat15 P;
  if constexpr (kCov) P = in.cov_s;
  EulerStepJacobian J;
  const std::size_t steps = w.size() - 1;
  const ImuSample* k0 = &w[0];
  for (std::size_t k = 0; k < steps; ++k) {
    const ImuSample* k1 = &w[k + 1];
    const double dt = k1->t - k0->t;
    if constexpr (kHold == Hold::Euler) {
      EulerStep<kPhi>(x, k0->gyro, k0->accel, dt, in.gravity, x, &J);
    } else {
      EulerStep<kPhi>(x, 0.5 * (k0->gyro + k1->gyro), 0.5 * (k0->accel + k1->accel), dt, in.gravity,
                      x, &J);
    }
    if constexpr (kPhi) PrependEulerStepBiasColumns(J, Phi);
    if constexpr (kCov) EulerCovarianceStep(J, q, P);
    k0 = k1;
  }
  out.x_e = x;
  if constexpr (kPhi) {
    ThetaColumnsFromState(in.x_s, x, w.t_end() - w.t_start(), in.gravity, Phi);
    out.Phi = Phi.ToMatrix();
  }
  if constexpr (kCov) out.cov = 0.5 * (P + P.transpose());  // remove rounding asymmetry once
}

/// The same propagation computed as a preintegration followed by the prediction (paper,
/// section 3.2, "propagation from preintegration"), without checking the input. Euler's
/// step over [t_k, t_k+1] and GTSAM's manifold preintegration step are the same map:
/// with R_s fixed, R_k = R_s dR_k, v_k = v_s + g (t_k - t_s) + R_s dv_k and
/// p_k = p_s + v_s (t_k - t_s) + g (t_k - t_s)^2/2 + R_s dp_k turn one into the other, and
/// the noise and bias random walk enter both identically. So the preintegration kernel's
/// per-sample recursion (4-lane SIMD, kernels/preintegration.h) does the per-sample
/// work, and the prediction runs once per interval:
///   start-frame increment errors (Exp(phi) dR, dp + e_p, dv + e_v; bias Jacobian H):
///     dtheta_e = dtheta_s + R_s phi,
///     dv_e = dv_s - [R_s dv]x dtheta_s + R_s e_v,
///     dp_e = dp_s + T dv_s - [R_s dp]x dtheta_s + R_s e_p,
///   with (phi, e_p, e_v) = H db_s + noise part, and db_e = db_s - delta b_k (the kernel's
///   bias error is minus the random walk, see kernels/preintegration.h). Hence
///     Phi = the left transition with th_bg = R_s H_tg, v_bg = R_s H_vg, v_ba = R_s H_va,
///           p_bg = R_s H_pg, p_ba = R_s H_pa and the theta columns from the state,
///     Sigma_e = Phi Sigma_s Phi^T + M Sigma_k M^T,  M = blockdiag(R_s, R_s, R_s, -I, -I)
///   after reordering [theta, p, v, ba, bg] to [p, theta, v, bg, ba] (paper, eq. prop-cov
///   with b_hat = b_s, where the bias-correction curvature vanishes).
/// kCov = false computes the state and Phi only (out.cov untouched).
namespace held_detail {

/// The preintegration kernel's input for a held propagation: the window at the start state's
/// biases.
inline PreintegrationInput StartFrameInput(const PropagationInput& in) {
  return PreintegrationInputOf(in.window, in.x_s.bg, in.x_s.ba, in.noise);
}

/// The end state from the start state and the start-frame increment (paper, eq.
/// prop-by-int-rot..b): R_e = R_s dR, v_e = v_s + T g + R_s dv, p_e = p_s + T v_s + T^2/2 g + R_s
/// dp.
inline void ComposeEndState(const PropagationInput& in, const ManifoldIncrement& inc,
                            ImuState& x_e) {
  const ImuState& x_s = in.x_s;
  const double T = in.window.t_end() - in.window.t_start();
  const Mat3& Rs = x_s.R;
  x_e.R = Rs * inc.dR;
  x_e.v = x_s.v + T * in.gravity + Rs * inc.dv;
  x_e.p = x_s.p + T * x_s.v + (0.5 * T * T) * in.gravity + Rs * inc.dp;
  x_e.bg = x_s.bg;
  x_e.ba = x_s.ba;
}

}  // namespace held_detail

template <Hold kHold, bool kCov>
inline Status IntegrateHeldByPreintegration(const PropagationInput& in, PropagationResult& out,
                                            Isa isa) {
  using namespace left_idx;
  const ImuState& x_s = in.x_s;
  StartFrameManifold pre;
  if (Status st =
          IntegrateManifoldStartFrame(held_detail::StartFrameInput(in), kHold, kCov, isa, pre);
      !st.ok())
    return st;
  held_detail::ComposeEndState(in, pre.increment, out.x_e);
  const ImuState& x_e = out.x_e;
  const double T = in.window.t_end() - in.window.t_start();
  const Mat3& Rs = x_s.R;

  const Mat96& H = pre.J_inc_bias;  // rows [theta, p, v], columns [ba, bg]
  LeftTransition Phi;
  Phi.th_bg.noalias() = Rs * H.block<3, 3>(0, 3);
  Phi.p_bg.noalias() = Rs * H.block<3, 3>(3, 3);
  Phi.v_bg.noalias() = Rs * H.block<3, 3>(6, 3);
  Phi.p_ba.noalias() = Rs * H.block<3, 3>(3, 0);
  Phi.v_ba.noalias() = Rs * H.block<3, 3>(6, 0);
  ThetaColumnsFromState(x_s, x_e, T, in.gravity, Phi);
  out.Phi = Phi.ToMatrix();

  if constexpr (kCov) {
    // M Sigma_k M^T: reorder and flip the bias rows and columns, then rotate the first nine.
    const Mat15& K = pre.cov;
    constexpr int kFrom[5] = {3, 0, 6, 12, 9};  // kernel block of left blocks p, theta, v, bg, ba
    constexpr double kSign[5] = {1, 1, 1, -1, -1};
    Mat15 S;
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j)
        S.block<3, 3>(3 * i, 3 * j) = (kSign[i] * kSign[j]) * K.block<3, 3>(kFrom[i], kFrom[j]);
    for (int b = 0; b < 9; b += 3) S.middleRows<3>(b) = Rs * S.middleRows<3>(b);
    for (int b = 0; b < 9; b += 3) S.middleCols<3>(b) = S.middleCols<3>(b) * Rs.transpose();
    // Phi Sigma_s Phi^T only where there is a start covariance (preintegration by
    // propagation starts from zero).
    if (!in.cov_s.isZero(0.0)) S += Congruence(Phi, in.cov_s);
    out.cov = 0.5 * (S + S.transpose());
  }
  return Status::Ok();
}

/// Integrates over the whole window without checking the input (see PropagateHeld). Fills
/// out.x_e, out.Phi and out.cov (whatever `kOut` asks for): the transition and covariance come
/// from the preintegration kernel's instance for this CPU (IntegrateHeldByPreintegration,
/// chosen once per interval), the baseline one included (SSE2 or NEON: 126 ns/sample against
/// 266 for the per-sample steps on the EPYC). Every mode runs the same compiled code (the
/// covariance instance), so the state and Phi are bitwise the same whatever else is asked
/// for: separate instances may fuse multiply-adds differently. The reduced modes serve finite
/// differences and Monte Carlo, not speed.
template <Hold kHold, Outputs kOut = Outputs::All>
inline void IntegrateHeld(const PropagationInput& in, PropagationResult& out) {
  (void)IntegrateHeldByPreintegration<kHold, true>(in, out,
                                                   BestIsa());  // BestIsa() is available: no error
}

/// The propagator entry point: checks the input, then integrates. Never throws except
/// std::bad_alloc while building an error message.
template <Hold kHold, Outputs kOut = Outputs::All>
inline Status PropagateHeld(const PropagationInput& in, PropagationResult& out) {
  Status st = CheckPropagationInput(in);
  if (st.ok()) IntegrateHeld<kHold, kOut>(in, out);
  return st;
}

}  // namespace imuconv::kernels
