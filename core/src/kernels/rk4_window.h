// Fourth-order integration in the `left` error state of the state, the transition matrix and
// the covariance, with the gyro and accel input interpolated linearly between knots (so the
// input is smooth inside a step and the order is kept); each knot interval may be split into
// `substeps` equal steps of length h (the plugin uses 1; tests halve the step with 2).
//
// The kernel keeps its name (and the plugin its id `rk4`): it started as one classical RK4
// system for state, Phi and P (still in tests/integrators/rk4_reference.h as a cross-check).
// The present form is fourth order in all three and costs a fraction of it; why it is built
// this way is below. This header is the kernel's code, compiled in imuconv_core only (once per
// instruction set, see "Instances" at the end); its public face is imuconv/kernels/rk4.h.
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
//      int_0^h (h - t) f = h^2/6 (f0 + 2 fm)         int_0^{h/2} (h/2 - t) f = h^2/96 (7 f0 + 6 fm
//      - f1)
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
#include "kernel_config.h"
#include "rk4_noise_sums.h"  // M = int Psi D Psi^T: its per-step sums and assembly (part 3)

IMUCONV_KERNEL_BEGIN
namespace rk4_detail {

/// [x]x B, column by column.
inline Mat3 SkewTimes(const Vec3& x, const Mat3& B) {
  Mat3 out;
  for (int j = 0; j < 3; ++j) out.col(j) = x.cross(B.col(j));
  return out;
}

/// Exp(phi) for phi = (x, y, z): I + a [phi]x + b [phi]x^2 (so3.h), written out entry by entry with
/// [phi]x^2 = phi phi^T - |phi|^2 I. Below so3's series threshold the series of a and b are
/// evaluated with multiplications by the reciprocals (no division, no square root): a step's
/// rotation is a few milliradians, so this is the branch every step takes.
inline Mat3 ExpOfStep(double x, double y, double z) {
  const double t2 = x * x + y * y + z * z;
  double a, b;
  constexpr double kSeries2 = so3::detail::kSeriesBelow * so3::detail::kSeriesBelow;
  if (t2 < kSeries2) {
    a = 1.0 - t2 * (1.0 / 6.0) *
                  (1.0 - t2 * (1.0 / 20.0) * (1.0 - t2 * (1.0 / 42.0) * (1.0 - t2 * (1.0 / 72.0))));
    b = 0.5 * (1.0 - t2 * (1.0 / 12.0) *
                         (1.0 - t2 * (1.0 / 30.0) *
                                    (1.0 - t2 * (1.0 / 56.0) * (1.0 - t2 * (1.0 / 90.0)))));
  } else {
    const double t = std::sqrt(t2);
    a = so3::detail::coefA(t, t2);
    b = so3::detail::coefB(t, t2);
  }
  const double bx = b * x, by = b * y, bz = b * z, ax = a * x, ay = a * y, az = a * z;
  const double d = 1.0 - b * t2;
  const double xy = bx * y, xz = bx * z, yz = by * z;
  Mat3 E;
  E << d + bx * x, xy - az, xz + ay,  //
      xy + az, d + by * y, yz - ax,   //
      xz - ay, yz + ax, d + bz * z;
  return E;
}

/// Everything the integration carries from one step to the next (values at the step's start).
struct Rk4Carry {
  // State: R, and U, W of the file comment; s = t - t_s at the step's start.
  Mat3 R;
  Vec3 U = Vec3::Zero(), W = Vec3::Zero();
  Vec3 Ra;  ///< R a at the node
  // Psi (as kOut asks): Y = [Pg; Vg; Pa; Tg] and Y' = [[alpha]x R; [U]x R; -s R; R] at the node.
  MatY Y = MatY::Zero(), dY = MatY::Zero();
  Vec3 alpha = Vec3::Zero();
  NoiseSums sums;

  Mat3 Tg() const { return Y.middleRows<3>(y_row::Tg); }
  Mat3 Pg() const { return Y.middleRows<3>(y_row::Pg); }
  Mat3 Vg() const { return Y.middleRows<3>(y_row::Vg); }
  Mat3 Pa() const { return Y.middleRows<3>(y_row::Pa); }
};

/// Y' = [[alpha]x R; [U]x R; -s R; R] at a node, column k of Y' (kYRows numbers) from column k
/// of R (column-major, 3 numbers): [alpha x r; U x r; -s r; r].
inline void FillDerivative(const double* R, double s, const double* alpha, const double* U,
                           double* dY) {
  for (int k = 0; k < 3; ++k) {
    const double* r = R + 3 * k;
    double* d = dY + kYRows * k;
    for (int i = 0; i < 3; ++i) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
      d[y_row::Pa + i] = -(s * r[i]);
      d[y_row::Tg + i] = r[i];
      d[y_row::Pg + i] = alpha[i1] * r[i2] - alpha[i2] * r[i1];
      d[y_row::Vg + i] = U[i1] * r[i2] - U[i2] * r[i1];
    }
  }
}

/// C = A B for column-major 3x3 arrays.
inline void Mul3(const double* A, const double* B, double* C) {
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      C[i + 3 * j] = A[i] * B[3 * j] + A[i + 3] * B[3 * j + 1] + A[i + 6] * B[3 * j + 2];
}

/// A x for a column-major 3x3 array.
inline void MulVec3(const double* A, const double* x, double* y) {
  for (int i = 0; i < 3; ++i) y[i] = A[i] * x[0] + A[i + 3] * x[1] + A[i + 6] * x[2];
}

/// Input of one step at its start and end, biases already removed (the middle is the mean).
struct Rk4StepInput {
  Vec3 w0, w1;  ///< body rate
  Vec3 a0, a1;  ///< specific force
};

/// One step of length h from s0 = t - t_s (see the file comment for the rules). `q` is only
/// read for Outputs::All.
template <Outputs kOut>
inline void Rk4Step(Rk4Carry& c, const Rk4StepInput& u, double h, double s0,
                    const NoiseVariances& q) {
  constexpr bool kPhi = WantsTransition(kOut), kCov = WantsCovariance(kOut);
  // The step is written over plain arrays (3-vectors, column-major 3x3 and 12x3 blocks) rather
  // than Eigen expressions: Eigen stores a 3-vector element by element and then loads it in
  // pairs, which defeats store-to-load forwarding at every temporary, and its packets are
  // fixed at 128 bits by the default target, where the loops below vectorise at each
  // instance's width. Divisions by constants are multiplications by their reciprocals (a
  // division costs several multiplications, and these sit on the step's critical path).
  const double h2 = h * h, h6 = h * (1.0 / 6.0);
  const double *w0 = u.w0.data(), *w1 = u.w1.data(), *a0 = u.a0.data(), *a1 = u.a1.data();
  // Rotation at the middle and the end (Magnus, linear rate).
  double phi_m[3], phi_1[3];
  {
    const double cm = 0.125 * h, c1 = 0.5 * h, km = h2 * (1.0 / 96.0), k1 = h2 * (1.0 / 12.0);
    for (int i = 0; i < 3; ++i) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
      const double wxw = w0[i1] * w1[i2] - w0[i2] * w1[i1];
      phi_m[i] = cm * (3.0 * w0[i] + w1[i]) + km * wxw;
      phi_1[i] = c1 * (w0[i] + w1[i]) + k1 * wxw;
    }
  }
  const Mat3 dRm = ExpOfStep(phi_m[0], phi_m[1], phi_m[2]);
  const Mat3 dR1 = ExpOfStep(phi_1[0], phi_1[1], phi_1[2]);
  double Rm[9], R1[9];
  Mul3(c.R.data(), dRm.data(), Rm);
  Mul3(c.R.data(), dR1.data(), R1);
  double a_m[3], Ram[3], Ra1[3], U1[3], W1[3];
  for (int i = 0; i < 3; ++i) a_m[i] = 0.5 * (a0[i] + a1[i]);
  MulVec3(Rm, a_m, Ram);
  MulVec3(R1, a1, Ra1);
  const double* Ra0 = c.Ra.data();
  const double* U0 = c.U.data();
  const double* W0 = c.W.data();
  const double k_w1 = h2 * (1.0 / 6.0);
  for (int i = 0; i < 3; ++i) {
    U1[i] = U0[i] + h6 * (Ra0[i] + 4.0 * Ram[i] + Ra1[i]);
    W1[i] = W0[i] + h * U0[i] + k_w1 * (Ra0[i] + 2.0 * Ram[i]);
  }

  if constexpr (kPhi) {
    const double sm = s0 + 0.5 * h, s1 = s0 + h;
    const double k_um = h * (1.0 / 24.0), k_wm = h2 * (1.0 / 96.0), half_h = 0.5 * h;
    double Um[3], alpha_m[3], alpha1[3];
    for (int i = 0; i < 3; ++i) {
      Um[i] = U0[i] + k_um * (5.0 * Ra0[i] + 8.0 * Ram[i] - Ra1[i]);
      const double Wm = W0[i] + half_h * U0[i] + k_wm * (7.0 * Ra0[i] + 6.0 * Ram[i] - Ra1[i]);
      alpha_m[i] = Wm - sm * Um[i];
      alpha1[i] = W1[i] - s1 * U1[i];
    }
    // Y' at the middle and the end (Pa' = -s R, Tg' = R, X' = G_theta R: Pg' = [alpha]x R, Vg' =
    // [U]x R).
    double dYm[kYSize], dY1[kYSize];
    FillDerivative(Rm, sm, alpha_m, Um, dYm);
    FillDerivative(R1, s1, alpha1, U1, dY1);
    // Step means Yb = Y0 + h/6 (Y'_0 + 2 Y'_m), then the end values
    // Y1 = Yb + h/6 (2 Y'_m + Y'_1) = Y0 + h/6 (Y'_0 + 4 Y'_m + Y'_1) (Simpson). The means are
    // formed in both modes so that Phi is bitwise the same with and without the covariance.
    MatY Yb;
    double twice_dYm[kYSize];
    {
      const double *y0 = c.Y.data(), *dy0 = c.dY.data();
      double* yb = Yb.data();
      for (int k = 0; k < 3; ++k)
        for (int i = kYRows * k; i < kYRows * (k + 1); ++i) {
          twice_dYm[i] = 2.0 * dYm[i];
          yb[i] = y0[i] + h6 * (dy0[i] + twice_dYm[i]);
        }
    }
    if constexpr (kCov) {
      NoiseSums& n = c.sums;
      // Walks: int_step X X^T = h Xb Xb^T + h^3/12 X'_m X'_m^T, the second term below.
      MatY hYb;
      for (int k = 0; k < 3; ++k)
        for (int i = kYRows * k; i < kYRows * (k + 1); ++i) hYb.data()[i] = h * Yb.data()[i];
      n.AddWalks(hYb, Yb);
      // q_g-type terms by the same step-mean rule on (alpha, U), alpha' = -s R a, U' = R a:
      //   int_step g g'^T = h gb gb'^T + h^3/12 g_m' g_m'^T for g, g' in {alpha, U}, so the
      //   derivative part is (R a)(R a)^T times s^2, -s, 1 (alpha alpha^T, U alpha^T, U U^T).
      // The walks' h^3/12 X'_m X'_m^T = h^3/12 G_theta G_theta^T joins the mean's weight
      // (G_theta at the mean instead of the middle: O(h^2) apart, O(h^5) in the step).
      const double h3 = h2 * h * (1.0 / 12.0);
      const double w = q.gyro * h + q.gyro_walk * h3, q_h3 = q.gyro * h3, sm2 = sm * sm;
      const double* alpha0 = c.alpha.data();
      double alpha_b[3], U_b[3], wa[3], wU[3], qRam[3];
      for (int i = 0; i < 3; ++i) {
        alpha_b[i] = alpha0[i] - h6 * (s0 * Ra0[i] + (2.0 * sm) * Ram[i]);
        U_b[i] = U0[i] + h6 * (Ra0[i] + 2.0 * Ram[i]);
        wa[i] = w * alpha_b[i];
        wU[i] = w * U_b[i];
        qRam[i] = q_h3 * Ram[i];
      }
      double *aa = n.aa.data(), *Ua = n.Ua.data(), *UU = n.UU.data();
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
          const double RaRa = qRam[i] * Ram[j];
          aa[i + 3 * j] += wa[i] * alpha_b[j] + sm2 * RaRa;
          Ua[i + 3 * j] += wU[i] * alpha_b[j] - sm * RaRa;
          UU[i + 3 * j] += wU[i] * U_b[j] + RaRa;
        }
      for (int i = 0; i < 3; ++i) {
        n.a[i] += wa[i];
        n.U[i] += wU[i];
      }
      n.h3 += h3;
      n.h3_s += h3 * sm;
      n.h3_ss += h3 * sm2;
    }
    {
      double *y = c.Y.data(), *dy = c.dY.data();
      const double* yb = Yb.data();
      for (int k = 0; k < 3; ++k)
        for (int i = kYRows * k; i < kYRows * (k + 1); ++i) {
          y[i] = yb[i] + h6 * (twice_dYm[i] + dY1[i]);
          dy[i] = dY1[i];
        }
    }
    for (int i = 0; i < 3; ++i) c.alpha[i] = alpha1[i];
  }

  for (int i = 0; i < 9; ++i) c.R.data()[i] = R1[i];
  for (int i = 0; i < 3; ++i) {
    c.Ra[i] = Ra1[i];
    c.U[i] = U1[i];
    c.W[i] = W1[i];
  }
}

/// Phi = Psi^{-1} from Psi's bias columns (block form; solve Psi c = e for each column):
///   th_bg = -Tg, v_bg = [U]x Tg - Vg, p_bg = [alpha]x Tg + T v_bg - Pg, v_ba = -Tg,
///   p_ba = -T Tg - Pa. The theta and v columns come from the state (ThetaColumnsFromState).
inline void PhiFromPsi(const Rk4Carry& c, double T, LeftTransition& Phi) {
  const Mat3 Tg = c.Tg();
  Phi.th_bg = -Tg;
  Phi.v_bg = SkewTimes(c.U, Tg) - c.Vg();
  Phi.p_bg = SkewTimes(c.alpha, Tg) + T * Phi.v_bg - c.Pg();
  Phi.v_ba = -Tg;
  Phi.p_ba = -T * Tg - c.Pa();
}

/// The integration over the whole window (see IntegrateRk4Window, kernels/rk4.h), as every
/// instance compiles it.
template <Outputs kOut>
inline void IntegrateWindow(const PropagationInput& in, PropagationResult& out, int substeps) {
  constexpr bool kPhi = WantsTransition(kOut), kCov = WantsCovariance(kOut);
  const SampleWindow& w = in.window;
  const NoiseVariances q(in.noise);
  const ImuState& xs = in.x_s;
  const double t_s = w.t_start();
  Rk4Carry c;
  c.R = xs.R;
  c.Ra = xs.R * (w[0].accel - xs.ba);
  c.dY.middleRows<3>(y_row::Tg) = xs.R;  // Y' at s = 0: Tg' = R, the rest 0 (alpha = U = 0)
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
    PhiFromPsi(c, T, Phi);
    ThetaColumnsFromState(xs, x, T, in.gravity, Phi);
    out.Phi = Phi.ToMatrix();
    if constexpr (kCov) {
      const Mat15 P = Congruence(Phi, in.cov_s + AssembleM(c.sums, q, T));
      out.cov = 0.5 * (P + P.transpose());
    }
  }
}

}  // namespace rk4_detail

// Instances. The step is 3x3 and 12x3 blocks over plain arrays; compiled for the default
// x86-64 target (SSE2) its loops run two numbers at a time. So with GCC on x86-64 the window's
// integration is also compiled for AVX2 + FMA and for AVX-512 (instance_avx2.cpp,
// instance_avx512.cpp, beside the preintegration kernel's recursion; dispatch.cpp picks the
// instance from the CPU), and for the default target once (rk4.cpp: the portable code, which
// is also the baseline instance's). Rk4Window is each instance's one entry: IMUCONV_RK4_TARGET
// and IMUCONV_RK4_CODEGEN (kernel_config.h) give it the instance's target, `flatten`, which inlines
// the whole step into it so that all of it is compiled for that instruction set (anything not
// inlined would stay default-target code, so nothing wide runs on a CPU without it), and
// fp-contract=off, which keeps GCC from fusing a * b + c into one multiply-add (its default,
// -ffp-contract=fast, would; aarch64 fuses at the default target too): the fused forms round
// differently, and which products get fused differs between the output modes, so the state
// would no longer be bitwise the same with and without Phi and P. Without fusing, vector and
// scalar code do the same operations in the same order: every instance gives the default
// target's outputs bitwise, and every output mode the same state
// (tests/integrators/rk4_instances.cpp), at about 10 % of the instances' speed. That is what
// makes montecarlo's mean-only trials (Outputs::State) the plugin's increments bit for bit:
// the same compiled function, the same operations (tests/integrators/mean_only.cpp).

#ifndef IMUCONV_RK4_TARGET
#define IMUCONV_RK4_TARGET
#endif

/// The whole window in the output mode asked (see IntegrateRk4Window, kernels/rk4.h).
IMUCONV_RK4_TARGET IMUCONV_RK4_CODEGEN inline void Rk4Window(const PropagationInput& in,
                                                             Outputs outputs, int substeps,
                                                             PropagationResult& out) {
  switch (outputs) {
    case Outputs::State:
      return rk4_detail::IntegrateWindow<Outputs::State>(in, out, substeps);
    case Outputs::StateAndTransition:
      return rk4_detail::IntegrateWindow<Outputs::StateAndTransition>(in, out, substeps);
    case Outputs::All:
      break;
  }
  rk4_detail::IntegrateWindow<Outputs::All>(in, out, substeps);
}

IMUCONV_KERNEL_END
