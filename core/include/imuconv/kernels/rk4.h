// Fourth-order integration in the `left` error state of the state, the transition matrix and
// the covariance, with the gyro and accel input interpolated linearly between knots (so the
// input is smooth inside a step and the order is kept); each knot interval may be split into
// `substeps` equal steps of length h (the plugin uses 1; tests halve the step with 2).
//
// The file keeps its name (and the plugin its id `rk4`): it started as one classical RK4
// system for state, Phi and P (still in tests/integrators/rk4_reference.h as a cross-check).
// The present form is fourth order in all three and costs a fraction of it; why it is built
// this way is below.
//
// 1. State (paper, eq. diff-state, noise-free): d/dt R = R [w]x, d/dt v = g + R a, d/dt p = v,
//    with w = w_m(t) - bg and a = a_m(t) - ba linear in t over a step. The rotation is the
//    fourth-order Magnus expansion, which for a linear w is
//      R(t0 + t) = R0 Exp(Omega(t)),  Omega(t) = int_0^t w + t^3/(12 h) w0 x w1  (+ O(t^5)),
//    i.e. Omega(h) = h/2 (w0 + w1) + h^2/12 w0 x w1 at the step's end and
//    Omega(h/2) = h/8 (3 w0 + w1) + h^2/96 w0 x w1 at its middle: two exponentials per step, a
//    true rotation at both, and a constant rate is integrated exactly. Everything else is a
//    quadrature of functions known at the nodes 0, h/2, h (the end node is the next step's
//    start, so each step evaluates two new nodes), with the rules that are exact for a
//    quadratic integrand f:
//      int_0^h f = h/6 (f0 + 4 fm + f1)              int_0^{h/2} f = h/24 (5 f0 + 8 fm - f1)
//      int_0^h (h - t) f = h^2/6 (f0 + 2 fm)         int_0^{h/2} (h/2 - t) f = h^2/96 (7 f0 + 6 fm - f1)
//    The full-step rules have local error O(h^5) (fourth order over the window); the
//    half-step ones O(h^4), which is enough: middle values only enter full-step rules, times h.
//    Velocity and position are kept as U = v - v_s - g s and W = p - p_s - v_s s - g s^2/2
//    (s = t - t_s), the integrals of R a.
//
// 2. Transition matrix. The error dynamics (paper, "IMU Propagation in Detail", eq. cont-error,
//    left chart, order [p, theta, v, bg, ba]) are
//      d dtheta/dt = -R dbg - R n_g,  d dv/dt = -[R a]x dtheta - R dba - R n_a,
//      d dp/dt = dv,                  d dbg/dt = n_wg,  d dba/dt = n_wa,
//    i.e. F(t) and G(t) with Qc = diag(q_g, q_a, q_wg, q_wa) (x) I. Instead of Phi(t, t_s) the
//    kernel integrates its inverse Psi(t) = Phi(t, t_s)^{-1}, which solves d Psi/dt = -Psi F and
//    has the same block form (left_transition.h). Its columns are
//      theta: [[alpha]x; I; [U]x; 0; 0],  alpha = -int s R a = W - s U   (from the state)
//      v:     [-s I; 0; I; 0; 0]
//      bg:    [Pg; Tg; Vg; I; 0],  Pg' = [alpha]x R,  Tg' = R,  Vg' = [U]x R
//      ba:    [Pa; 0; Tg; 0; I],   Pa' = -s R
//    so Psi's free part is the 9x3 X = [Pg; Tg; Vg] plus Pa, all plain quadratures of
//    X' = G_theta R (G_theta = Psi's theta column), by the rules above. Phi = Psi^{-1} follows in
//    closed form once per window (PhiFromPsi); its theta columns come from the state
//    (ThetaColumnsFromState), exactly as the variational equations give them.
//
// 3. Covariance. dP/dt = F P + P F^T + D with D = G Qc G^T = diag(0, q_g, q_a, q_wg, q_wa) (x) I
//    (state independent since R R^T = I) has, by variation of constants, the solution
//      P(t_e) = Phi_e (P_s + M) Phi_e^T,   M = int Psi D Psi^T dt
//    which is the paper's eq. prop-cov with Phi_e = Phi_{e|s} and G Sigma_Dx G^T = Phi_e M Phi_e^T.
//    Per noise, Psi D Psi^T = q c c^T for Psi's column c of that noise:
//      q_g  c_theta c_theta^T: blocks [alpha]x[alpha]x^T = |alpha|^2 I - alpha alpha^T,
//           [alpha]x[U]x^T = (alpha.U) I - U alpha^T, ...: sums of 3-vector outer products;
//      q_a  c_v c_v^T = [s^2 I, -s I; -s I, I] in (p, v): closed form in T = t_e - t_s;
//      q_wg X X^T and the linear blocks int X; q_wa [Pa; Tg][Pa; Tg]^T likewise: 3x3 products.
//    They are integrated by one rule per step rather than per node: for y, z smooth inside
//    the step (the input is), Taylor expansion about the step's middle gives
//      int_step y z^T = h yb zb^T + h^3/12 y'_m z'_m^T + O(h^5),   yb = step mean of y,
//    with yb = y0 + h/6 (y'_0 + 2 y'_m) a rule of the list above, and y'_m z'_m^T needed only
//    to O(h^2). The derivative products are cheap: X' X'^T = G_theta R R^T G_theta^T =
//    G_theta G_theta^T (the q_g form again), [-s R; R][-s R; R]^T = [s^2 I, -s I; -s I, I],
//    and for (alpha, U) all three outer products are (R a)(R a)^T times s^2, -s, 1. So a step
//    costs one set of 3x3 products (of the means) and one of 3-vector outer products.
//    The congruence with Phi_e is once per window, in block form.
//
// All quadratures share the nodes of the state, so state, Phi and P are fourth order in h
// (tests/integrators/rk4_convergence.cpp checks the 16x per halving for all three, and
// rk4_cross_check.cpp the agreement with the classical RK4 to O(h^4)). Nothing allocates.
#pragma once

#include "imuconv/kernels/common.h"
#include "imuconv/kernels/left_transition.h"

namespace imuconv::kernels {

namespace rk4_detail {

/// M's accumulators: M = int Psi D Psi^T assembled from them once per window (AssembleM).
struct NoiseSums {
  // q_g-type terms: sums of weighted outer products of (alpha, U), the weights including the
  // noise densities (see Rk4Step).
  Mat3 aa = Mat3::Zero(), Ua = Mat3::Zero(), UU = Mat3::Zero();  ///< alpha alpha^T, U alpha^T, U U^T
  Vec3 a = Vec3::Zero(), U = Vec3::Zero();
  // Walk corrections of the c_v-type (closed-form) terms: sum h^3/12 {1, s_m, s_m^2}.
  double h3 = 0.0, h3_s = 0.0, h3_ss = 0.0;
  // Sum over steps of h Xb Xb^T blocks (gyro walk) and of the accel walk's [Pa; Tg] blocks.
  Mat3 PgPg = Mat3::Zero(), PgTg = Mat3::Zero(), PgVg = Mat3::Zero();
  Mat3 TgTg = Mat3::Zero(), TgVg = Mat3::Zero(), VgVg = Mat3::Zero();
  Mat3 PaPa = Mat3::Zero(), PaTg = Mat3::Zero();
  // Sum over steps of h Xb: int Pg, int Tg, int Vg, int Pa.
  Mat3 iPg = Mat3::Zero(), iTg = Mat3::Zero(), iVg = Mat3::Zero(), iPa = Mat3::Zero();

  /// w g g'^T for g, g' in {alpha, U} (and w alpha, w U).
  void AddWeighted(const Vec3& alpha, const Vec3& U_, double w) {
    const Vec3 wa = w * alpha, wU = w * U_;
    aa.noalias() += wa * alpha.transpose();
    Ua.noalias() += wU * alpha.transpose();
    UU.noalias() += wU * U_.transpose();
    a += wa;
    U += wU;
  }
};

/// [x]x B, column by column.
inline Mat3 SkewTimes(const Vec3& x, const Mat3& B) {
  Mat3 out;
  for (int j = 0; j < 3; ++j) out.col(j) = x.cross(B.col(j));
  return out;
}

/// Everything the integration carries from one step to the next (values at the step's start).
struct Rk4Carry {
  // State: R, and U, W of the file comment; s = t - t_s at the step's start.
  Mat3 R;
  Vec3 U = Vec3::Zero(), W = Vec3::Zero();
  Vec3 Ra;  ///< R a at the node
  // Psi (as kOut asks): X = [Pg; Tg; Vg], Pa, and X' at the node (Tg' = R needs no copy).
  Mat3 Pg = Mat3::Zero(), Tg = Mat3::Zero(), Vg = Mat3::Zero(), Pa = Mat3::Zero();
  Mat3 dPg = Mat3::Zero(), dVg = Mat3::Zero();
  Vec3 alpha = Vec3::Zero();
  NoiseSums sums;
};

}  // namespace rk4_detail

/// Input of one step at its start and end, biases already removed (the middle is the mean).
struct Rk4StepInput {
  Vec3 w0, w1;  ///< body rate
  Vec3 a0, a1;  ///< specific force
};

/// One step of length h from s0 = t - t_s (see the file comment for the rules). `q` is only
/// read for Outputs::All.
template <Outputs kOut>
inline void Rk4Step(rk4_detail::Rk4Carry& c, const Rk4StepInput& u, double h, double s0, const NoiseVariances& q) {
  constexpr bool kPhi = WantsTransition(kOut), kCov = WantsCovariance(kOut);
  // Rotation at the middle and the end (Magnus, linear rate).
  const Vec3 wxw = u.w0.cross(u.w1);
  const double h2 = h * h;
  Mat3 dRm, dR1;
  ExpAndJr((0.125 * h) * (3.0 * u.w0 + u.w1) + (h2 / 96.0) * wxw, dRm, nullptr);
  ExpAndJr((0.5 * h) * (u.w0 + u.w1) + (h2 / 12.0) * wxw, dR1, nullptr);
  const Mat3 R0 = c.R;
  Mat3 Rm, R1;
  Rm.noalias() = R0 * dRm;
  R1.noalias() = R0 * dR1;
  const Vec3 Ra0 = c.Ra;
  const Vec3 Ram = Rm * (0.5 * (u.a0 + u.a1));
  const Vec3 Ra1 = R1 * u.a1;
  const double h6 = h / 6.0;
  const Vec3 U0 = c.U;
  const Vec3 U1 = U0 + h6 * (Ra0 + 4.0 * Ram + Ra1);
  const Vec3 W1 = c.W + h * U0 + (h2 / 6.0) * (Ra0 + 2.0 * Ram);

  if constexpr (kPhi) {
    using rk4_detail::SkewTimes;
    const double sm = s0 + 0.5 * h, s1 = s0 + h;
    const Vec3 Um = U0 + (h / 24.0) * (5.0 * Ra0 + 8.0 * Ram - Ra1);
    const Vec3 Wm = c.W + (0.5 * h) * U0 + (h2 / 96.0) * (7.0 * Ra0 + 6.0 * Ram - Ra1);
    const Vec3 alpha0 = c.alpha, alpha_m = Wm - sm * Um, alpha1 = W1 - s1 * U1;
    // X' = G_theta R at the middle and the end.
    const Mat3 dPgm = SkewTimes(alpha_m, Rm), dVgm = SkewTimes(Um, Rm);
    const Mat3 dPg1 = SkewTimes(alpha1, R1), dVg1 = SkewTimes(U1, R1);
    // Step means Xb = X0 + h/6 (X'_0 + 2 X'_m) (Pa' = -s R likewise), then the end values
    // X1 = Xb + h/6 (2 X'_m + X'_1) = X0 + h/6 (X'_0 + 4 X'_m + X'_1) (Simpson). The means are
    // formed in both modes so that Phi is bitwise the same with and without the covariance.
    const Mat3 Tgb = c.Tg + h6 * (R0 + 2.0 * Rm);
    const Mat3 Pgb = c.Pg + h6 * (c.dPg + 2.0 * dPgm);
    const Mat3 Vgb = c.Vg + h6 * (c.dVg + 2.0 * dVgm);
    const Mat3 Pab = c.Pa - h6 * (s0 * R0 + (2.0 * sm) * Rm);
    if constexpr (kCov) {
      rk4_detail::NoiseSums& n = c.sums;
      // Walks: int_step X X^T = h Xb Xb^T + h^3/12 X'_m X'_m^T, the second term below.
      const Mat3 hTgb = h * Tgb, hPgb = h * Pgb, hVgb = h * Vgb, hPab = h * Pab;
      n.PgPg.noalias() += hPgb * Pgb.transpose();
      n.PgTg.noalias() += hPgb * Tgb.transpose();
      n.PgVg.noalias() += hPgb * Vgb.transpose();
      n.TgTg.noalias() += hTgb * Tgb.transpose();
      n.TgVg.noalias() += hTgb * Vgb.transpose();
      n.VgVg.noalias() += hVgb * Vgb.transpose();
      n.PaPa.noalias() += hPab * Pab.transpose();
      n.PaTg.noalias() += hPab * Tgb.transpose();
      n.iPg += hPgb;
      n.iTg += hTgb;
      n.iVg += hVgb;
      n.iPa += hPab;
      // q_g-type terms by the same step-mean rule on (alpha, U), alpha' = -s R a, U' = R a:
      //   int_step g g'^T = h gb gb'^T + h^3/12 g_m' g_m'^T for g, g' in {alpha, U}, so the
      //   derivative part is (R a)(R a)^T times s^2, -s, 1 (alpha alpha^T, U alpha^T, U U^T).
      // The walks' h^3/12 X'_m X'_m^T = h^3/12 G_theta G_theta^T joins the mean's weight
      // (G_theta at the mean instead of the middle: O(h^2) apart, O(h^5) in the step).
      const double h3 = h2 * h / 12.0;
      const Vec3 alpha_b = alpha0 - h6 * (s0 * Ra0 + (2.0 * sm) * Ram);
      const Vec3 U_b = U0 + h6 * (Ra0 + 2.0 * Ram);
      n.AddWeighted(alpha_b, U_b, q.gyro * h + q.gyro_walk * h3);
      const Vec3 qRam = (q.gyro * h3) * Ram;
      const Mat3 RaRa = qRam * Ram.transpose();
      n.aa += (sm * sm) * RaRa;
      n.Ua -= sm * RaRa;
      n.UU += RaRa;
      n.h3 += h3;
      n.h3_s += h3 * sm;
      n.h3_ss += h3 * sm * sm;
    }
    c.Tg = Tgb + h6 * (2.0 * Rm + R1);
    c.Pg = Pgb + h6 * (2.0 * dPgm + dPg1);
    c.Vg = Vgb + h6 * (2.0 * dVgm + dVg1);
    c.Pa = Pab - h6 * ((2.0 * sm) * Rm + s1 * R1);
    c.dPg = dPg1;
    c.dVg = dVg1;
    c.alpha = alpha1;
  }

  c.R = R1;
  c.Ra = Ra1;
  c.U = U1;
  c.W = W1;
}

namespace rk4_detail {

/// Phi = Psi^{-1} from Psi's bias columns (block form; solve Psi c = e for each column):
///   th_bg = -Tg, v_bg = [U]x Tg - Vg, p_bg = [alpha]x Tg + T v_bg - Pg, v_ba = -Tg,
///   p_ba = -T Tg - Pa. The theta and v columns come from the state (ThetaColumnsFromState).
inline void PhiFromPsi(const Rk4Carry& c, double T, LeftTransition& Phi) {
  Phi.th_bg = -c.Tg;
  Phi.v_bg = SkewTimes(c.U, c.Tg) - c.Vg;
  Phi.p_bg = SkewTimes(c.alpha, c.Tg) + T * Phi.v_bg - c.Pg;
  Phi.v_ba = -c.Tg;
  Phi.p_ba = -T * c.Tg - c.Pa;
}

/// M = int_{t_s}^{t_e} Psi D Psi^T from the sums (lower triangle filled by symmetry).
inline Mat15 AssembleM(const NoiseSums& n, const NoiseVariances& q, double T) {
  using namespace left_idx;
  const Mat3 I = Mat3::Identity();
  // c_v-type scalars: q_a int {1, s, s^2} in closed form plus the accel walk's corrections.
  const double c1 = q.accel * T + q.accel_walk * n.h3;
  const double cs = q.accel * (0.5 * T * T) + q.accel_walk * n.h3_s;
  const double css = q.accel * (T * T * T / 3.0) + q.accel_walk * n.h3_ss;
  const double c_theta = q.gyro * T + q.gyro_walk * n.h3;  // the sum of the q_g-type weights
  Mat15 M = Mat15::Zero();
  M.block<3, 3>(p, p) = (n.aa.trace() + css) * I - n.aa + q.gyro_walk * n.PgPg + q.accel_walk * n.PaPa;
  M.block<3, 3>(p, theta) = so3::skew(n.a) + q.gyro_walk * n.PgTg;
  M.block<3, 3>(p, v) = (n.Ua.trace() - cs) * I - n.Ua + q.gyro_walk * n.PgVg + q.accel_walk * n.PaTg;
  M.block<3, 3>(p, bg) = q.gyro_walk * n.iPg;
  M.block<3, 3>(p, ba) = q.accel_walk * n.iPa;
  M.block<3, 3>(theta, theta) = c_theta * I + q.gyro_walk * n.TgTg;
  M.block<3, 3>(theta, v) = -so3::skew(n.U) + q.gyro_walk * n.TgVg;
  M.block<3, 3>(theta, bg) = q.gyro_walk * n.iTg;
  M.block<3, 3>(v, v) = (n.UU.trace() + c1) * I - n.UU + q.gyro_walk * n.VgVg + q.accel_walk * n.TgTg;
  M.block<3, 3>(v, bg) = q.gyro_walk * n.iVg;
  M.block<3, 3>(v, ba) = q.accel_walk * n.iTg;
  M.block<3, 3>(bg, bg) = (q.gyro_walk * T) * I;
  M.block<3, 3>(ba, ba) = (q.accel_walk * T) * I;
  M.triangularView<Eigen::StrictlyLower>() = M.transpose();
  return M;
}

}  // namespace rk4_detail

/// Integrates over the whole window with `substeps` steps per knot interval, without
/// checking the input (see PropagateRk4). Fills out.x_e, and out.Phi and out.cov as asked.
template <Outputs kOut = Outputs::All>
inline void IntegrateRk4(const PropagationInput& in, PropagationResult& out, int substeps = 1) {
  constexpr bool kPhi = WantsTransition(kOut), kCov = WantsCovariance(kOut);
  const SampleWindow& w = in.window;
  const NoiseVariances q(in.noise);
  const ImuState& xs = in.x_s;
  const double t_s = w.t_start();
  rk4_detail::Rk4Carry c;
  c.R = xs.R;
  c.Ra = xs.R * (w[0].accel - xs.ba);
  const std::size_t intervals = w.size() - 1;
  const double inv_n = 1.0 / substeps;
  const ImuSample* k0 = &w[0];
  Rk4StepInput u;
  for (std::size_t k = 0; k < intervals; ++k) {
    const ImuSample* k1 = &w[k + 1];
    const double dt = k1->t - k0->t, s0 = k0->t - t_s;
    const Vec3 w_k0 = k0->gyro - xs.bg, a_k0 = k0->accel - xs.ba;
    const Vec3 w_k1 = k1->gyro - xs.bg, a_k1 = k1->accel - xs.ba;
    if (substeps == 1) {
      u.w0 = w_k0, u.w1 = w_k1, u.a0 = a_k0, u.a1 = a_k1;
      Rk4Step<kOut>(c, u, dt, s0, q);
    } else {
      const Vec3 dw = w_k1 - w_k0, da = a_k1 - a_k0;
      const double h = dt * inv_n;
      u.w1 = w_k0, u.a1 = a_k0;
      for (int i = 0; i < substeps; ++i) {
        // Linear interpolation at the substep's end (a fraction of dt).
        const double s_end = (i + 1) * inv_n;
        u.w0 = u.w1, u.a0 = u.a1;
        u.w1 = i + 1 == substeps ? w_k1 : Vec3(w_k0 + s_end * dw);
        u.a1 = i + 1 == substeps ? a_k1 : Vec3(a_k0 + s_end * da);
        Rk4Step<kOut>(c, u, h, s0 + i * h, q);
      }
    }
    k0 = k1;
  }
  const double T = w.t_end() - t_s;
  ImuState& x = out.x_e;
  x = xs;  // the biases are constant
  x.R = c.R;
  x.v = xs.v + c.U + T * in.gravity;
  x.p = xs.p + T * xs.v + (0.5 * T * T) * in.gravity + c.W;
  if constexpr (kPhi) {
    LeftTransition Phi;
    rk4_detail::PhiFromPsi(c, T, Phi);
    ThetaColumnsFromState(xs, x, T, in.gravity, Phi);
    out.Phi = Phi.ToMatrix();
    if constexpr (kCov) {
      const Mat15 P = Congruence(Phi, in.cov_s + rk4_detail::AssembleM(c.sums, q, T));
      out.cov = 0.5 * (P + P.transpose());
    }
  }
}

/// The propagator entry point: checks the input (and substeps >= 1), then integrates.
template <Outputs kOut = Outputs::All>
inline Status PropagateRk4(const PropagationInput& in, PropagationResult& out, int substeps = 1) {
  if (substeps < 1) return Status::Error("rk4: substeps must be at least 1");
  Status st = CheckPropagationInput(in);
  if (st.ok()) IntegrateRk4<kOut>(in, out, substeps);
  return st;
}

}  // namespace imuconv::kernels
