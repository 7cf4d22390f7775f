// Compile-time kernels of GTSAM's two preintegration schemes, with the covariance of
// PreintegratedCombinedMeasurements and the first-order bias Jacobians.
//
//   manifold: the increment (dR, dp, dv) is a NavState updated on the manifold
//             (GTSAM's ManifoldPreintegration);
//   tangent:  the increment is the 9-vector xi = [theta, p, v] with dR = Exp(theta),
//             integrated in the tangent space at the identity (GTSAM's
//             TangentPreintegration).
//
// Both are driven with a zero-order hold: knot j of the window is held over
// [t_j, t_j+1] (the discrete form of the paper's eq. preint-theta..preint-v). Each step
// yields its Jacobians in GTSAM's notation,
//   A = d x' / d x (9x9),  B = d x' / d acc (9x3),  C = d x' / d omega (9x3),
// which drive both the bias Jacobians (inputs move by minus the bias change)
//   H_ba' = A H_ba - B,   H_bg' = A H_bg - C,
// and the covariance of the 15-state [theta, p, v, ba, bg] (GTSAM's preintMeasCov order):
//   F = [A  Fb; 0  I6],  Fb = [0 C_theta; B_p 0; B_v 0],
//   Sigma' = F Sigma F^T + diag(B (s_a^2/dt) B^T + C (s_g^2/dt) C^T,  dt q_a^2 I, dt q_g^2 I),
// (s_a, s_g: white-noise densities; q_a, q_g: random-walk densities; GTSAM's
// integrationCovariance and biasAccOmegaInit are zero), i.e. the first-order discrete
// propagation of the paper's section 2.1 with the bias
// random walk Delta b (eq. preint-b) appended. The bias error state of that covariance is
// delta b = -Delta b (paper, "GTSAM Peculiarities", eq. preint-error-db), which is why Fb
// enters with the sign of d x'/d(acc, omega) rather than of d x'/d(bias).
//
// One chart for the recursion. Both schemes are propagated in a chart whose p and v parts
// are additive in the start frame (tangent: xi itself; manifold: dR Exp(dtheta), dp + ddp,
// dv + ddv, i.e. `gtsam_manifold_jacobian`). In it every step has the same pattern
//   A = [A_tt 0 0; K dt/2  I  I dt; K  0  I],  B = [0; N dt^2/2; N dt],  C = [C_t; 0; 0]
// with N a rotation, so both schemes share one bias-Jacobian and one covariance routine.
// The manifold covariance is wanted in the NavState chart (dp + dR dp, dv + dR dv, paper
// eq. residual-error); the two charts differ by the exact linear map
// blockdiag(I, dR^T, dR^T) at the estimate, applied once at the end. This is the same
// linearisation as GTSAM's per-step NavState Jacobians, rearranged.
//
// Structure relied on for speed: the pattern above, theta not depending on the
// accelerometer (so cov(dtheta, dba) and d theta/d ba stay zero), and isotropic noise
// (ImuNoise holds scalar densities), which keeps the bias block of Sigma at
// t * diag(q_a^2 I, q_g^2 I) and makes B B^T identity blocks. Everything is fixed-size;
// the per-sample loop never touches the heap.
#pragma once

#include <cmath>
#include <string>

#include "imuconv/preintegrator.h"
#include "imuconv/so3.h"
#include "imuconv/status.h"
#include "imuconv/types.h"
#include "imuconv/window.h"

namespace imuconv::kernels {

using Mat93 = Eigen::Matrix<double, 9, 3>;

// ---------------------------------------------------------------------------------------
// SO(3) coefficients, each set from one sin/cos evaluation.

namespace detail {

/// [phi]x^2 = phi phi^T - |phi|^2 I, without a matrix product.
inline Mat3 SkewSquared(const Vec3& phi, double t2) {
  Mat3 S2 = phi * phi.transpose();
  S2.diagonal().array() -= t2;
  return S2;
}

/// e(t) = d'(t)/t for d(t) = 1/t^2 - cot(t/2)/(2t), the [phi]x^2 coefficient of Jr^{-1}.
/// Series: d(t) = sum_{n>=1} |B_2n|/(2n)! t^(2n-2) (Bernoulli numbers, from the Laurent
/// series of cot), so e(t) = sum_{n>=2} (2n-2)|B_2n|/(2n)! t^(2n-4). Below t = 0.5 the
/// terms shrink by t^2/(4 pi^2) < 0.0064, so seven terms leave < 5e-16 relative. Above,
/// the closed form e = (1/(4 sin^2(t/2)) - 1/t^2 - d)/t^2 loses at most ~30/t^2 ulps
/// (< 3e-14 relative).
inline double DPrimeOverTSeries(double t2) {
  constexpr double e0 = 2.0 / 720.0;                                 // n = 2
  constexpr double e1 = 4.0 / 30240.0;                               // n = 3
  constexpr double e2 = 6.0 / 1209600.0;                             // n = 4
  constexpr double e3 = 8.0 / 47900160.0;                            // n = 5
  constexpr double e4 = 10.0 * 691.0 / 1307674368000.0;              // n = 6
  constexpr double e5 = 12.0 * 7.0 / 523069747200.0;                 // n = 7
  constexpr double e6 = 14.0 * 3617.0 / (510.0 * 20922789888000.0);  // n = 8
  return e0 + t2 * (e1 + t2 * (e2 + t2 * (e3 + t2 * (e4 + t2 * (e5 + t2 * e6)))));
}
constexpr double kDPrimeSeriesBelow = 0.5;

/// Coefficients of Exp = I + a S + b S^2, Jr = I - b S + c S^2 (S = [phi]x, t = |phi|).
struct ExpJrCoefs {
  double a, b, c;
};
inline ExpJrCoefs ComputeExpJrCoefs(double t, double t2) {
  using namespace so3::detail;
  if (t < kSeriesBelow) return {coefA(t, t2), coefB(t, t2), coefC(t, t2)};  // no trig
  const double sh = std::sin(0.5 * t), ch = std::cos(0.5 * t), sin_t = 2.0 * sh * ch;
  return {sin_t / t, 2.0 * sh * sh / t2, (t - sin_t) / (t2 * t)};
}

/// ... plus Jr^{-1} = I + S/2 + d S^2 and e = d'(t)/t, for the tangent scheme.
struct TangentCoefs {
  double a, b, c, d, e;
};
inline TangentCoefs ComputeTangentCoefs(double t, double t2) {
  using namespace so3::detail;
  TangentCoefs k;
  if (t < kSeriesBelow) {
    k = {coefA(t, t2), coefB(t, t2), coefC(t, t2), coefD(t, t2), DPrimeOverTSeries(t2)};
    return k;
  }
  const double sh = std::sin(0.5 * t), ch = std::cos(0.5 * t), sin_t = 2.0 * sh * ch;
  k.a = sin_t / t;
  k.b = 2.0 * sh * sh / t2;
  k.c = (t - sin_t) / (t2 * t);
  k.d = 1.0 / t2 - 0.5 * ch / (t * sh);  // cot(t/2) = cos/sin of the half angle
  k.e = t < kDPrimeSeriesBelow ? DPrimeOverTSeries(t2) : (0.25 / (sh * sh) - 1.0 / t2 - k.d) / t2;
  return k;
}

/// d/dtheta [Jr^{-1}(theta) omega] given theta's coefficients d and e. From
///   Jr^{-1}(theta) omega = omega + 1/2 theta x omega + d(t) theta x (theta x omega),
///   d/dtheta [theta x (theta x omega)] = (theta.omega) I + theta omega^T - 2 omega theta^T,
///   d/dtheta d(|theta|) = (d'(t)/t) theta^T.
inline Mat3 JrInvTimesVecDerivative(const Vec3& theta, const Vec3& omega, double d, double e) {
  const Vec3 txtxw = theta.cross(theta.cross(omega));
  Mat3 D = -0.5 * so3::skew(omega);
  D.noalias() += theta * (d * omega).transpose();
  D.noalias() += (e * txtxw - 2.0 * d * omega) * theta.transpose();
  D.diagonal().array() += d * theta.dot(omega);
  return D;
}

}  // namespace detail

/// d/dtheta [Jr^{-1}(theta) omega] for fixed omega: the exact derivative of the tangent
/// scheme's angular-rate map w_tangent = Jr^{-1}(theta) omega.
inline Mat3 JrInvTimesVecDerivative(const Vec3& theta, const Vec3& omega) {
  const double t2 = theta.squaredNorm(), t = std::sqrt(t2);
  const detail::TangentCoefs k = detail::ComputeTangentCoefs(t, t2);
  return detail::JrInvTimesVecDerivative(theta, omega, k.d, k.e);
}

// ---------------------------------------------------------------------------------------
// One step's Jacobians, in block form, in the additive-p,v chart (see the header comment).

/// A, B, C of one step:
///   A = [A_tt 0 0; K dt/2  I  I dt; K  0  I],
///   B = [0; N dt^2/2; N dt],  C = [C_t; 0; 0].
struct StepJacobians {
  double dt = 0.0;
  Mat3 A_tt;  ///< d theta' / d theta
  Mat3 K;     ///< d v' / d theta (and 2/dt d p' / d theta)
  Mat3 N;     ///< rotation of the accelerometer input into the start frame
  Mat3 C_t;   ///< d theta' / d omega

  Mat9 A() const {
    Mat9 a = Mat9::Identity();
    a.block<3, 3>(0, 0) = A_tt;
    a.block<3, 3>(3, 0) = (0.5 * dt) * K;
    a.block<3, 3>(3, 6).diagonal().setConstant(dt);
    a.block<3, 3>(6, 0) = K;
    return a;
  }
  Mat93 B() const {
    Mat93 b = Mat93::Zero();
    b.block<3, 3>(3, 0) = (0.5 * dt * dt) * N;
    b.block<3, 3>(6, 0) = dt * N;
    return b;
  }
  Mat93 C() const {
    Mat93 c = Mat93::Zero();
    c.block<3, 3>(0, 0) = C_t;
    return c;
  }
};

/// A Z for a 9x3 column block Z = [Z_t; Z_p; Z_v] (two 3x3 products).
inline Mat93 ApplyA(const StepJacobians& J, const Mat93& Z) {
  Mat93 Y;
  const Mat3 KZt = J.K * Z.block<3, 3>(0, 0);
  Y.block<3, 3>(0, 0).noalias() = J.A_tt * Z.block<3, 3>(0, 0);
  Y.block<3, 3>(3, 0) = (0.5 * J.dt) * KZt + Z.block<3, 3>(3, 0) + J.dt * Z.block<3, 3>(6, 0);
  Y.block<3, 3>(6, 0) = KZt + Z.block<3, 3>(6, 0);
  return Y;
}

/// A Z for a column block whose theta rows are zero (they stay zero; no products).
inline Mat93 ApplyAThetaFree(double dt, const Mat93& Z) {
  Mat93 Y;
  Y.block<3, 3>(0, 0).setZero();
  Y.block<3, 3>(3, 0) = Z.block<3, 3>(3, 0) + dt * Z.block<3, 3>(6, 0);
  Y.block<3, 3>(6, 0) = Z.block<3, 3>(6, 0);
  return Y;
}

// ---------------------------------------------------------------------------------------
// Bias Jacobians, shared by both schemes.

/// d x / d(ba, bg) in the additive-p,v chart; rows [theta, p, v]. The theta rows of H_ba
/// stay zero: theta does not see the accelerometer.
struct BiasJacobians {
  Mat93 H_ba = Mat93::Zero();
  Mat93 H_bg = Mat93::Zero();

  /// 9x6, columns [ba, bg] (GTSAM's layout).
  Mat96 Assemble() const {
    Mat96 J;
    J.leftCols<3>() = H_ba;
    J.rightCols<3>() = H_bg;
    return J;
  }
};

/// H_ba' = A H_ba - B, H_bg' = A H_bg - C, with the Jacobians of the state before the step.
inline void PropagateBiasJacobians(const StepJacobians& J, BiasJacobians& H) {
  const double dt = J.dt, h = 0.5 * dt * dt;
  H.H_ba = ApplyAThetaFree(dt, H.H_ba);
  H.H_ba.block<3, 3>(3, 0) -= h * J.N;
  H.H_ba.block<3, 3>(6, 0) -= dt * J.N;
  H.H_bg = ApplyA(J, H.H_bg);
  H.H_bg.block<3, 3>(0, 0) -= J.C_t;
}

// ---------------------------------------------------------------------------------------
// Covariance of PreintegratedCombinedMeasurements, kept in blocks.

/// Discrete noise variances: gyro/accel white noise density^2 (divided by dt per step),
/// bias random walks density^2 (multiplied by dt per step). GTSAM's
/// integrationCovariance and biasAccOmegaInit are zero here.
struct NoiseVariances {
  double gyro = 0.0, accel = 0.0, gyro_rw = 0.0, accel_rw = 0.0;
  static NoiseVariances FromDensities(const ImuNoise& n) {
    return {n.gyro_noise_density * n.gyro_noise_density, n.accel_noise_density * n.accel_noise_density,
            n.gyro_random_walk * n.gyro_random_walk, n.accel_random_walk * n.accel_random_walk};
  }
};

/// Sigma = [P X; X^T S] with P = cov(delta x9), X = cov(delta x9, delta b) (columns
/// [ba, bg]) and S = diag(s_ba I3, s_bg I3): with isotropic random walks and zero initial
/// bias uncertainty the bias block is exactly the accumulated random walk, and the
/// theta rows of the ba columns of X stay zero.
struct CombinedCovariance {
  Mat9 P = Mat9::Zero();
  Mat96 X = Mat96::Zero();
  double s_ba = 0.0, s_bg = 0.0;

  Mat15 Assemble() const {
    Mat15 S = Mat15::Zero();
    S.topLeftCorner<9, 9>() = P;
    S.block<9, 6>(0, 9) = X;
    S.block<6, 9>(9, 0) = X.transpose();
    S.block<3, 3>(9, 9).diagonal().setConstant(s_ba);
    S.block<3, 3>(12, 12).diagonal().setConstant(s_bg);
    return S;
  }
};

/// Sigma' = F Sigma F^T + G Q G^T for one step (see the header comment), in 3x3 blocks.
///
/// Rather than multiplying 9x9 and 15x15 matrices, the step is written through the few
/// 3-vectors it is linear in:
///   theta~ = A_tt theta,  u = K theta,  g = C_t (db_g + n_g),  w = N (db_a + n_a),
///   q = p + dt v,  r = u + dt w,
///   theta' = theta~ + g,  p' = q + (dt/2) r,  v' = v + r,
/// so every 3x3 product is one of these maps applied to a block of Sigma (17 products a
/// step), the rest are scaled sums, and the diagonal blocks come out symmetric. With the
/// noise and the bias block isotropic, cov(w, w) = (s_ba + s_a^2/dt) I, and g is
/// correlated with the state only through the bias columns of X; w is uncorrelated with
/// theta (cov(dtheta, dba) = 0).
/// PreintegratedImuMeasurements' 9x9 covariance is P of this recursion run with zero
/// random walk (X and the bias block then stay zero).
inline void PropagateCombined(const StepJacobians& J, const NoiseVariances& q, CombinedCovariance& c) {
  const double dt = J.dt, half_dt = 0.5 * dt, h = 0.5 * dt * dt;
  const double kw = c.s_ba + q.accel / dt;  // cov(w, w) = kw I (N is a rotation)
  const double kg = c.s_bg + q.gyro / dt;   // cov(g, g) = kg C_t C_t^T

  const auto blk = [](auto& M, int i, int j) { return M.template block<3, 3>(3 * i, 3 * j); };
  const Mat3 Ptt = blk(c.P, 0, 0), Ptp = blk(c.P, 0, 1), Ptv = blk(c.P, 0, 2);
  const Mat3 Ppp = blk(c.P, 1, 1), Ppv = blk(c.P, 1, 2), Pvv = blk(c.P, 2, 2);
  const Mat3 Xp_a = c.X.block<3, 3>(3, 0), Xv_a = c.X.block<3, 3>(6, 0);
  const Mat3 Xt_g = c.X.block<3, 3>(0, 3), Xp_g = c.X.block<3, 3>(3, 3), Xv_g = c.X.block<3, 3>(6, 3);
  const Mat3 Ptq = Ptp + dt * Ptv;     // cov(theta, q)
  const Mat3 Xq_a = Xp_a + dt * Xv_a;  // cov(q, db_a)
  const Mat3 Xq_g = Xp_g + dt * Xv_g;  // cov(q, db_g)

  // theta~ and u against theta, q, v.
  const Mat3 AP = J.A_tt * Ptt, KP = J.K * Ptt;
  Mat3 TT = AP * J.A_tt.transpose();  // cov(theta~, theta~)
  const Mat3 TU = AP * J.K.transpose();  // cov(theta~, u)
  Mat3 UU = KP * J.K.transpose();        // cov(u, u)
  const Mat3 Tq = J.A_tt * Ptq, Tv = J.A_tt * Ptv;
  const Mat3 Uq = J.K * Ptq, Uv = J.K * Ptv;
  // Bias columns through the step: A applied to X's bg column.
  const Mat3 AXg = J.A_tt * Xt_g, KXg = J.K * Xt_g;
  // cov(., g) for theta~, v' and p' (without their own g or w parts).
  const Mat3 Ct_T = J.C_t.transpose();
  const Mat3 Gt = AXg * Ct_T;
  const Mat3 Gv = (Xv_g + KXg) * Ct_T;
  const Mat3 Gp = (Xq_g + half_dt * KXg) * Ct_T;
  Mat3 CC = J.C_t * Ct_T;
  // cov(., w) for q and v.
  const Mat3 Nt = J.N.transpose();
  const Mat3 Wq = Xq_a * Nt, Wv = Xv_a * Nt;

  // r = u + dt w.
  const Mat3 Rq = Uq + dt * Wq.transpose();  // cov(r, q)
  const Mat3 Rv = Uv + dt * Wv.transpose();  // cov(r, v)
  UU.diagonal().array() += dt * dt * kw;     // now cov(r, r)
  const Mat3& RR = UU;
  // Symmetrise the three products that are symmetric in exact arithmetic.
  TT = 0.5 * (TT + TT.transpose()).eval();
  CC = 0.5 * (CC + CC.transpose()).eval();
  const Mat3 RRs = 0.5 * (RR + RR.transpose());

  const Mat3 Pqq = Ppp + dt * (Ppv + Ppv.transpose()) + (dt * dt) * Pvv;
  const Mat3 Pqv = Ppv + dt * Pvv;

  // Symmetric parts are summed first so the diagonal blocks stay exactly symmetric.
  const Mat3 Ntt = TT + (Gt + Gt.transpose()) + kg * CC;
  const Mat3 Ntp = Tq + half_dt * TU + Gp.transpose();
  const Mat3 Ntv = Tv + TU + Gv.transpose();
  const Mat3 Npp = Pqq + half_dt * (Rq + Rq.transpose()) + (half_dt * half_dt) * RRs;
  const Mat3 Npv = Pqv + Rq.transpose() + half_dt * Rv + half_dt * RRs;
  const Mat3 Nvv = Pvv + (Rv + Rv.transpose()) + RRs;

  blk(c.P, 0, 0) = Ntt;
  blk(c.P, 0, 1) = Ntp;
  blk(c.P, 0, 2) = Ntv;
  blk(c.P, 1, 0) = Ntp.transpose();
  blk(c.P, 1, 1) = Npp;
  blk(c.P, 1, 2) = Npv;
  blk(c.P, 2, 0) = Ntv.transpose();
  blk(c.P, 2, 1) = Npv.transpose();
  blk(c.P, 2, 2) = Nvv;

  // X' = A X + Fb S.
  c.X.block<3, 3>(3, 0) = Xq_a + (h * c.s_ba) * J.N;
  c.X.block<3, 3>(6, 0) = Xv_a + (dt * c.s_ba) * J.N;
  c.X.block<3, 3>(0, 3) = AXg + c.s_bg * J.C_t;
  c.X.block<3, 3>(3, 3) = Xq_g + half_dt * KXg;
  c.X.block<3, 3>(6, 3) = Xv_g + KXg;

  c.s_ba += dt * q.accel_rw;
  c.s_bg += dt * q.gyro_rw;
}

// ---------------------------------------------------------------------------------------
// Manifold scheme (ManifoldPreintegration).

/// Increment of the manifold scheme and its bias Jacobians (GTSAM's delRdelBiasOmega,
/// delPdelBiasAcc, ...): rotation rows w.r.t. a right perturbation dR Exp(dtheta),
/// position and velocity rows additive.
struct ManifoldIncrement {
  double dt = 0.0;
  Mat3 dR = Mat3::Identity();
  Vec3 dp = Vec3::Zero(), dv = Vec3::Zero();
  BiasJacobians H;
};

/// One zero-order-hold step of the manifold scheme with bias-corrected inputs
/// acc = a_m - ba_hat, omega = w_m - bg_hat held over dt:
///   dp' = dp + dv dt + dR acc dt^2/2,  dv' = dv + dR acc dt,  dR' = dR Exp(omega dt).
/// Jacobians in the chart (dR Exp(dtheta), dp + ddp, dv + ddv), with E = Exp(omega dt)
/// and dR the rotation before the step:
///   A_tt = E^T,  K = -dR [acc]x dt,  N = dR,  C_t = Jr(omega dt) dt.
/// The bias Jacobians that follow are GTSAM's delRdelBiasOmega etc.: the exact
/// derivatives of this discrete map w.r.t. the bias estimate.
inline void ManifoldStep(const Vec3& acc, const Vec3& omega, double dt, ManifoldIncrement& s, StepJacobians& J) {
  const double h = 0.5 * dt * dt;
  const Vec3 phi = omega * dt;
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const detail::ExpJrCoefs k = detail::ComputeExpJrCoefs(t, t2);
  const Mat3 S = so3::skew(phi), S2 = detail::SkewSquared(phi, t2);
  const Mat3 E = Mat3::Identity() + k.a * S + k.b * S2;
  const Mat3 Jr = Mat3::Identity() - k.b * S + k.c * S2;

  J.dt = dt;
  J.A_tt = E.transpose();
  J.K.noalias() = (-dt) * s.dR * so3::skew(acc);
  J.N = s.dR;
  J.C_t = dt * Jr;
  PropagateBiasJacobians(J, s.H);

  const Vec3 a_start = s.dR * acc;  // acceleration in the start frame
  s.dp += dt * s.dv + h * a_start;
  s.dv += dt * a_start;
  s.dR = s.dR * E;
  s.dt += dt;
}

/// The manifold covariance in the NavState chart (dR Exp(dth), dp + dR ddp, dv + dR ddv):
/// Sigma_nav = T Sigma T^T with T = blockdiag(I, dR^T, dR^T, I6) at the final estimate.
inline Mat15 ManifoldCovarianceInNavStateChart(const Mat3& dR, const CombinedCovariance& c) {
  Mat15 S = c.Assemble();
  const Mat3 Rt = dR.transpose();
  for (int blk = 3; blk <= 6; blk += 3) {
    S.block<3, 15>(blk, 0) = Rt * S.block<3, 15>(blk, 0);
    S.block<15, 3>(0, blk) = S.block<15, 3>(0, blk) * dR;
  }
  return 0.5 * (S + S.transpose());  // rows and columns were rotated in separate roundings
}

// ---------------------------------------------------------------------------------------
// Tangent scheme (TangentPreintegration).

/// Increment of the tangent scheme: xi = [theta, p, v] with dR = Exp(theta), and
/// d xi / d(ba, bg) additive on xi (GTSAM's preintegrated_H_biasAcc/Omega).
struct TangentIncrement {
  double dt = 0.0;
  Vec9 xi = Vec9::Zero();
  BiasJacobians H;
};

/// One zero-order-hold step of the tangent scheme, with R = Exp(theta):
///   theta' = theta + Jr^{-1}(theta) omega dt,
///   p' = p + v dt + R acc dt^2/2,  v' = v + R acc dt.
/// Exact Jacobians in the additive chart of xi, with d(R acc)/dtheta = -R [acc]x Jr(theta):
///   A_tt = I + d(Jr^{-1}(theta) omega)/dtheta dt,  K = -R [acc]x Jr(theta) dt,
///   N = R,  C_t = Jr^{-1}(theta) dt.
inline void TangentStep(const Vec3& acc, const Vec3& omega, double dt, TangentIncrement& s, StepJacobians& J) {
  const double h = 0.5 * dt * dt;
  const Vec3 theta = s.xi.segment<3>(0);
  const double t2 = theta.squaredNorm(), t = std::sqrt(t2);
  const detail::TangentCoefs k = detail::ComputeTangentCoefs(t, t2);
  const Mat3 S = so3::skew(theta), S2 = detail::SkewSquared(theta, t2);
  const Mat3 R = Mat3::Identity() + k.a * S + k.b * S2;
  const Mat3 Jr = Mat3::Identity() - k.b * S + k.c * S2;
  const Mat3 JrInv = Mat3::Identity() + 0.5 * S + k.d * S2;

  J.dt = dt;
  J.A_tt = Mat3::Identity() + dt * detail::JrInvTimesVecDerivative(theta, omega, k.d, k.e);
  J.K.noalias() = (-dt) * (R * so3::skew(acc)) * Jr;
  J.N = R;
  J.C_t = dt * JrInv;
  PropagateBiasJacobians(J, s.H);

  const Vec3 a_start = R * acc;
  s.xi.segment<3>(3) += dt * s.xi.segment<3>(6) + h * a_start;
  s.xi.segment<3>(6) += dt * a_start;
  s.xi.segment<3>(0) += dt * (JrInv * omega);
  s.dt += dt;
}

// ---------------------------------------------------------------------------------------
// Interval drivers.

/// Checks what the drivers rely on: at least two knots, finite data, strictly increasing
/// time, non-negative finite noise. Allocates only to report an error.
inline Status CheckPreintegrationInput(const PreintegrationInput& in) {
  const SampleWindow& w = in.window;
  if (w.end < w.begin || w.size() < 2) return Status::Error("window has fewer than 2 knots");
  if (w.end > w.begin && w.samples == nullptr) return Status::Error("window has interior knots but no samples");
  if (!in.bg.allFinite() || !in.ba.allFinite()) return Status::Error("bias estimate is not finite");
  const ImuNoise& n = in.noise;
  for (double q : {n.gyro_noise_density, n.accel_noise_density, n.gyro_random_walk, n.accel_random_walk})
    if (!(std::isfinite(q) && q >= 0.0)) return Status::Error("noise densities must be finite and non-negative");
  const std::size_t count = w.size();
  for (std::size_t j = 0; j < count; ++j) {
    const ImuSample& s = w[j];
    if (!std::isfinite(s.t) || !s.gyro.allFinite() || !s.accel.allFinite())
      return Status::Error("knot " + std::to_string(j) + " of the window is not finite");
    if (j > 0 && !(s.t > w[j - 1].t))
      return Status::Error("knot times must increase strictly (knot " + std::to_string(j) + ")");
  }
  return Status::Ok();
}

/// Runs Step(acc, omega, dt, increment, J) over the window with zero-order hold: knot j,
/// bias-corrected with (bg, ba), held over [t_j, t_j+1]; and, if kCovariance, the
/// combined covariance.
template <bool kCovariance, typename Increment, typename StepFn>
inline void RunZeroOrderHold(const PreintegrationInput& in, StepFn step, Increment& inc, CombinedCovariance& cov) {
  const SampleWindow& w = in.window;
  const NoiseVariances q = NoiseVariances::FromDensities(in.noise);
  const std::size_t count = w.size();
  StepJacobians J;
  for (std::size_t j = 0; j + 1 < count; ++j) {
    const ImuSample& s = w[j];
    const double dt = w[j + 1].t - s.t;
    step(s.accel - in.ba, s.gyro - in.bg, dt, inc, J);
    if constexpr (kCovariance) PropagateCombined(J, q, cov);
  }
}

inline void FillCommon(const PreintegrationInput& in, double dt, const BiasJacobians& H, NativePreintegration& out) {
  out.dt = dt;
  out.delta.dbg.setZero();
  out.delta.dba.setZero();
  out.bg_hat = in.bg;
  out.ba_hat = in.ba;
  out.J_bias = H.Assemble();
}

/// Manifold scheme over the window; covariance in the NavState chart ("gtsam_manifold"),
/// bias Jacobian in dR Exp(dtheta), additive dp, dv ("gtsam_manifold_jacobian").
/// Without kCovariance, out.cov is zero (for re-integrations that need the mean only).
template <bool kCovariance = true>
inline Status IntegrateManifold(const PreintegrationInput& in, NativePreintegration& out,
                                ManifoldIncrement* increment = nullptr) {
  Status st = CheckPreintegrationInput(in);
  if (!st.ok()) return st;
  ManifoldIncrement inc;
  CombinedCovariance cov;
  RunZeroOrderHold<kCovariance>(
      in, [](const Vec3& a, const Vec3& w, double dt, ManifoldIncrement& x, StepJacobians& J) { ManifoldStep(a, w, dt, x, J); },
      inc, cov);
  FillCommon(in, inc.dt, inc.H, out);
  out.delta.dR = inc.dR;
  out.delta.dp = inc.dp;
  out.delta.dv = inc.dv;
  if constexpr (kCovariance) out.cov = ManifoldCovarianceInNavStateChart(inc.dR, cov);
  else out.cov.setZero();
  if (increment) *increment = inc;
  return Status::Ok();
}

/// Tangent scheme over the window; covariance and bias Jacobian additive on the tangent
/// 9-vector ("gtsam_tangent"). Without kCovariance, out.cov is zero.
template <bool kCovariance = true>
inline Status IntegrateTangent(const PreintegrationInput& in, NativePreintegration& out,
                               TangentIncrement* increment = nullptr) {
  Status st = CheckPreintegrationInput(in);
  if (!st.ok()) return st;
  TangentIncrement inc;
  CombinedCovariance cov;
  RunZeroOrderHold<kCovariance>(
      in, [](const Vec3& a, const Vec3& w, double dt, TangentIncrement& x, StepJacobians& J) { TangentStep(a, w, dt, x, J); },
      inc, cov);
  FillCommon(in, inc.dt, inc.H, out);
  out.delta.dR = so3::Exp(inc.xi.segment<3>(0));
  out.delta.dp = inc.xi.segment<3>(3);
  out.delta.dv = inc.xi.segment<3>(6);
  if constexpr (kCovariance) out.cov = cov.Assemble();
  else out.cov.setZero();
  if (increment) *increment = inc;
  return Status::Ok();
}

}  // namespace imuconv::kernels
