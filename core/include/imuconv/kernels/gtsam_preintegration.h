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
// [t_j, t_j+1] (the discrete form of the paper's eq. preint-theta..preint-v). Every step
// also yields its Jacobians in GTSAM's notation,
//   A = d x' / d x (9x9),  B = d x' / d acc (9x3),  C = d x' / d omega (9x3),
// in the scheme's own chart of the increment, and those drive one covariance recursion
// shared by both schemes (15 states, order [theta, p, v, ba, bg] as GTSAM's preintMeasCov):
//
//   F = [A  Fb; 0  I6],  Fb = [0 C_theta; B_p 0; B_v 0]
//   Sigma' = F Sigma F^T + diag(B (s_a^2/dt) B^T + C (s_g^2/dt) C^T,  dt q_a^2 I, dt q_g^2 I)
//
// i.e. the first-order discrete propagation of the paper's section 2.1 with the bias
// random walk Delta b (eq. preint-b) appended. The bias error state of that covariance is
// delta b = -Delta b (paper, "GTSAM Peculiarities", eq. preint-error-db), which is why
// Fb enters with the sign of d x'/d(acc, omega) rather than of d x'/d(bias).
//
// Structure used (and relied on): every block of A has the pattern
//   A = [A_tt 0 0; A_pt M dt*M; A_vt 0 M]
// (M = I for tangent, M = Exp(omega dt)^T for manifold), B's p and v blocks are one
// rotation N times dt^2/2 and dt, C has only theta rows, and the noise is isotropic
// (ImuNoise holds scalar densities), so the bias block of Sigma stays t * diag(q_a^2 I,
// q_g^2 I). The per-step work is a handful of fixed-size 3x3 products and never touches
// the heap.
#pragma once

#include <cmath>

#include "imuconv/preintegrator.h"
#include "imuconv/so3.h"
#include "imuconv/status.h"
#include "imuconv/types.h"
#include "imuconv/window.h"

namespace imuconv::kernels {

using Mat93 = Eigen::Matrix<double, 9, 3>;

// ---------------------------------------------------------------------------------------
// SO(3) helper the tangent scheme needs and so3.h does not have.

namespace detail {
// e(t) = d'(t)/t for d(t) = 1/t^2 - cot(t/2)/(2t), the [phi]x^2 coefficient of Jr^{-1}.
// Series: d(t) = sum_{n>=1} |B_2n|/(2n)! t^(2n-2) (Bernoulli numbers, from the Laurent
// series of cot), so e(t) = sum_{n>=2} (2n-2)|B_2n|/(2n)! t^(2n-4). Below t = 0.5 the
// terms shrink by t^2/(4 pi^2) < 0.0064, so eight terms leave < 1e-16 relative. Above,
// the closed form e = (1/(4 sin^2(t/2)) - 1/t^2 - d)/t^2 loses at most ~30/t^2 ulps
// (< 3e-13 relative), far below what the callers need.
inline double coefDPrimeOverT(double t, double t2) {
  if (t < 0.5) {
    constexpr double e0 = 2.0 / 720.0;                                    // n = 2
    constexpr double e1 = 4.0 / 30240.0;                                  // n = 3
    constexpr double e2 = 6.0 / 1209600.0;                                // n = 4
    constexpr double e3 = 8.0 / 47900160.0;                               // n = 5
    constexpr double e4 = 10.0 * 691.0 / 1307674368000.0;                 // n = 6
    constexpr double e5 = 12.0 * 7.0 / 523069747200.0;                    // n = 7
    constexpr double e6 = 14.0 * 3617.0 / (510.0 * 20922789888000.0);     // n = 8
    return e0 + t2 * (e1 + t2 * (e2 + t2 * (e3 + t2 * (e4 + t2 * (e5 + t2 * e6)))));
  }
  const double s = std::sin(0.5 * t);
  return (0.25 / (s * s) - 1.0 / t2 - so3::detail::coefD(t, t2)) / t2;
}
}  // namespace detail

/// d/dtheta [Jr^{-1}(theta) omega] for fixed omega: the exact derivative of the tangent
/// scheme's angular-rate map w_tangent = Jr^{-1}(theta) omega. From
///   Jr^{-1}(theta) omega = omega + 1/2 theta x omega + d(t) theta x (theta x omega),
///   d/dtheta [theta x (theta x omega)] = (theta.omega) I + theta omega^T - 2 omega theta^T,
///   d/dtheta d(|theta|) = (d'(t)/t) theta^T.
inline Mat3 JrInvTimesVecDerivative(const Vec3& theta, const Vec3& omega) {
  const double t2 = theta.squaredNorm(), t = std::sqrt(t2);
  const double d = so3::detail::coefD(t, t2);
  const double e = detail::coefDPrimeOverT(t, t2);
  const Vec3 txtxw = theta.cross(theta.cross(omega));
  Mat3 D = -0.5 * so3::skew(omega);
  D += d * (theta * omega.transpose() - 2.0 * omega * theta.transpose());
  D.diagonal().array() += d * theta.dot(omega);
  D.noalias() += e * txtxw * theta.transpose();
  return D;
}

// ---------------------------------------------------------------------------------------
// One step's Jacobians, in block form.

/// A, B, C of one step (see the header comment for the pattern):
///   A = [A_tt 0 0; A_pt M dt*M; A_vt 0 M],
///   B = [0; N dt^2/2; N dt],  C = [C_t; 0; 0].
struct StepJacobians {
  double dt = 0.0;
  Mat3 A_tt, A_pt, A_vt;
  Mat3 M;   ///< p/v self-block of A
  Mat3 N;   ///< rotation of the accelerometer input into the p/v rows of B
  Mat3 C_t;  ///< theta rows of C
  bool M_is_identity = false;

  Mat9 A() const {
    Mat9 a = Mat9::Zero();
    a.block<3, 3>(0, 0) = A_tt;
    a.block<3, 3>(3, 0) = A_pt;
    a.block<3, 3>(3, 3) = M;
    a.block<3, 3>(3, 6) = dt * M;
    a.block<3, 3>(6, 0) = A_vt;
    a.block<3, 3>(6, 6) = M;
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
/// bias uncertainty the bias block is exactly the accumulated random walk.
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

/// Y = A Z for a 9x3 column block Z = [Z_t; Z_p; Z_v], with A's pattern.
inline Mat93 ApplyA(const StepJacobians& J, const Mat93& Z) {
  Mat93 Y;
  const Mat3 Zt = Z.block<3, 3>(0, 0);
  const Mat3 Zpv = Z.block<3, 3>(3, 0) + J.dt * Z.block<3, 3>(6, 0);
  Y.block<3, 3>(0, 0).noalias() = J.A_tt * Zt;
  Y.block<3, 3>(3, 0).noalias() = J.A_pt * Zt;
  Y.block<3, 3>(6, 0).noalias() = J.A_vt * Zt;
  if (J.M_is_identity) {
    Y.block<3, 3>(3, 0) += Zpv;
    Y.block<3, 3>(6, 0) += Z.block<3, 3>(6, 0);
  } else {
    Y.block<3, 3>(3, 0).noalias() += J.M * Zpv;
    Y.block<3, 3>(6, 0).noalias() += J.M * Z.block<3, 3>(6, 0);
  }
  return Y;
}

/// Sigma' = F Sigma F^T + G Q G^T for one step (see the header comment), in blocks:
///   X' = A X + Fb S,
///   P' = A P A^T + (A X) Fb^T + Fb (A X)^T + Fb S Fb^T + B (s_a^2/dt) B^T + C (s_g^2/dt) C^T,
/// where, with S and the noise isotropic, Fb S Fb^T + noise = (s_bg + s_g^2/dt) C C^T on
/// theta-theta and (s_ba + s_a^2/dt) B B^T on p/v, and B B^T has identity blocks because N
/// is a rotation. PreintegratedImuMeasurements' 9x9 covariance is P of this recursion run
/// with zero random walk (X and S then stay zero).
inline void PropagateCombined(const StepJacobians& J, const NoiseVariances& q, CombinedCovariance& c) {
  const double dt = J.dt, h = 0.5 * dt * dt;
  // T = A P, then P' = T A^T; both through ApplyA on the three column blocks.
  Mat9 T;
  for (int j = 0; j < 3; ++j) T.block<9, 3>(0, 3 * j) = ApplyA(J, c.P.block<9, 3>(0, 3 * j));
  Mat9 Pn;
  // (T A^T) = (A T^T)^T; T^T's column blocks are T's row blocks transposed.
  for (int i = 0; i < 3; ++i) Pn.block<9, 3>(0, 3 * i) = ApplyA(J, T.block<3, 9>(3 * i, 0).transpose());
  // Pn now holds (A P A^T)^T with column block i = A (T row block i)^T; A P A^T is
  // symmetric in exact arithmetic, and symmetrising below removes the rounding asymmetry.

  // Y = A X: the cross covariance carried through the step.
  Mat96 Y;
  Y.leftCols<3>() = ApplyA(J, c.X.leftCols<3>());
  Y.rightCols<3>() = ApplyA(J, c.X.rightCols<3>());

  // Z = Y Fb^T: column blocks theta <- Y_bg C_t^T, p <- Y_ba (h N)^T, v <- Y_ba (dt N)^T.
  Mat9 Z;
  const Mat3 Nt = J.N.transpose();
  Z.block<9, 3>(0, 0).noalias() = Y.rightCols<3>() * J.C_t.transpose();
  const Mat93 YbaNt = Y.leftCols<3>() * Nt;
  Z.block<9, 3>(0, 3) = h * YbaNt;
  Z.block<9, 3>(0, 6) = dt * YbaNt;

  Pn += Z + Z.transpose();
  // Fb S Fb^T plus the measurement noise; B B^T = [h^2 I, h dt I; h dt I, dt^2 I] since N
  // is a rotation.
  const double ka = c.s_ba + q.accel / dt, kg = c.s_bg + q.gyro / dt;
  Pn.block<3, 3>(0, 0).noalias() += kg * (J.C_t * J.C_t.transpose());
  Pn.block<3, 3>(3, 3).diagonal().array() += ka * h * h;
  Pn.block<3, 3>(3, 6).diagonal().array() += ka * h * dt;
  Pn.block<3, 3>(6, 3).diagonal().array() += ka * h * dt;
  Pn.block<3, 3>(6, 6).diagonal().array() += ka * dt * dt;
  c.P = 0.5 * (Pn + Pn.transpose());

  // X' = Y + Fb S: theta rows gain s_bg C_t in the bg columns, p/v rows s_ba B in ba.
  c.X = Y;
  c.X.block<3, 3>(0, 3) += c.s_bg * J.C_t;
  c.X.block<3, 3>(3, 0) += (c.s_ba * h) * J.N;
  c.X.block<3, 3>(6, 0) += (c.s_ba * dt) * J.N;

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
  Mat3 dR_dbg = Mat3::Zero();
  Mat3 dp_dba = Mat3::Zero(), dp_dbg = Mat3::Zero();
  Mat3 dv_dba = Mat3::Zero(), dv_dbg = Mat3::Zero();

  /// 9x6, rows [theta, p, v], columns [ba, bg] (GTSAM's layout).
  Mat96 BiasJacobian() const {
    Mat96 J = Mat96::Zero();
    J.block<3, 3>(0, 3) = dR_dbg;
    J.block<3, 3>(3, 0) = dp_dba;
    J.block<3, 3>(3, 3) = dp_dbg;
    J.block<3, 3>(6, 0) = dv_dba;
    J.block<3, 3>(6, 3) = dv_dbg;
    return J;
  }
};

/// One zero-order-hold step of the manifold scheme with bias-corrected inputs
/// acc = a_m - ba_hat, omega = w_m - bg_hat held over dt:
///   dp' = dp + dv dt + dR acc dt^2/2,  dv' = dv + dR acc dt,  dR' = dR Exp(omega dt).
/// Its Jacobians in the NavState chart (dR Exp(dth), dp + dR ddp, dv + dR ddv), with
/// E = Exp(omega dt):
///   A = [E^T 0 0; -E^T[acc]x dt^2/2  E^T  E^T dt; -E^T[acc]x dt  0  E^T],
///   B = [0; E^T dt^2/2; E^T dt],  C = [Jr(omega dt) dt; 0; 0].
/// The bias Jacobians are the exact derivatives of this discrete map w.r.t. the bias
/// estimate (acc and omega move by -d ba, -d bg) and use the rotation before the step.
template <bool kJacobians>
inline void ManifoldStep(const Vec3& acc, const Vec3& omega, double dt, ManifoldIncrement& s,
                         StepJacobians* J) {
  const double h = 0.5 * dt * dt;
  const Vec3 phi = omega * dt;
  const Mat3 E = so3::Exp(phi);
  const Mat3 Jr = so3::Jr(phi);
  const Mat3 Et = E.transpose();

  // Bias Jacobians first: they need the increment before the step.
  // d(dR acc)/d(bg) through the rotation = -dR [acc]x (d dtheta / d bg).
  const Mat3 dRacc_dbg = -s.dR * so3::skew(acc) * s.dR_dbg;
  s.dp_dba += dt * s.dv_dba - h * s.dR;
  s.dp_dbg += dt * s.dv_dbg + h * dRacc_dbg;
  s.dv_dba -= dt * s.dR;
  s.dv_dbg += dt * dRacc_dbg;
  s.dR_dbg = Et * s.dR_dbg - dt * Jr;

  const Vec3 a_start = s.dR * acc;  // acceleration in the start frame
  s.dp += dt * s.dv + h * a_start;
  s.dv += dt * a_start;
  s.dR = s.dR * E;
  s.dt += dt;

  if constexpr (kJacobians) {
    const Mat3 Et_acc = Et * so3::skew(acc);
    J->dt = dt;
    J->A_tt = Et;
    J->A_pt = -h * Et_acc;
    J->A_vt = -dt * Et_acc;
    J->M = Et;
    J->N = Et;
    J->C_t = dt * Jr;
    J->M_is_identity = false;
  }
}

// ---------------------------------------------------------------------------------------
// Tangent scheme (TangentPreintegration).

/// Increment of the tangent scheme: xi = [theta, p, v] with dR = Exp(theta), and
/// d xi / d(ba, bg) additive on xi (GTSAM's preintegrated_H_biasAcc/Omega).
struct TangentIncrement {
  double dt = 0.0;
  Vec9 xi = Vec9::Zero();
  Mat93 H_ba = Mat93::Zero();  ///< theta rows stay zero: theta does not see the accelerometer
  Mat93 H_bg = Mat93::Zero();

  Mat96 BiasJacobian() const {
    Mat96 J;
    J.leftCols<3>() = H_ba;
    J.rightCols<3>() = H_bg;
    return J;
  }
};

/// One zero-order-hold step of the tangent scheme, with R = Exp(theta):
///   theta' = theta + Jr^{-1}(theta) omega dt,
///   p' = p + v dt + R acc dt^2/2,  v' = v + R acc dt.
/// Its exact Jacobians in the additive chart of xi, with K = d(R acc)/d theta =
/// -R [acc]x Jr(theta):
///   A = [I + d(Jr^{-1} omega)/dtheta dt  0  0; K dt^2/2  I  I dt; K dt  0  I],
///   B = [0; R dt^2/2; R dt],  C = [Jr^{-1}(theta) dt; 0; 0].
/// Bias Jacobians: H_ba' = A H_ba - B, H_bg' = A H_bg - C (inputs move by -d bias).
template <bool kJacobians>
inline void TangentStep(const Vec3& acc, const Vec3& omega, double dt, TangentIncrement& s,
                        StepJacobians* J) {
  const double h = 0.5 * dt * dt;
  const Vec3 theta = s.xi.segment<3>(0);
  const Mat3 R = so3::Exp(theta);
  const Mat3 Jr = so3::Jr(theta);
  const Mat3 JrInv = so3::JrInv(theta);
  const Vec3 w_tangent = JrInv * omega;
  const Vec3 a_start = R * acc;

  StepJacobians Jl;
  Jl.dt = dt;
  Jl.A_tt = Mat3::Identity() + dt * JrInvTimesVecDerivative(theta, omega);
  const Mat3 K = -R * so3::skew(acc) * Jr;
  Jl.A_pt = h * K;
  Jl.A_vt = dt * K;
  Jl.M.setIdentity();
  Jl.M_is_identity = true;
  Jl.N = R;
  Jl.C_t = dt * JrInv;

  // Bias Jacobians with the Jacobians at the state before the step.
  Mat93 H_ba = ApplyA(Jl, s.H_ba);
  H_ba.block<3, 3>(3, 0) -= h * R;
  H_ba.block<3, 3>(6, 0) -= dt * R;
  s.H_ba = H_ba;
  Mat93 H_bg = ApplyA(Jl, s.H_bg);
  H_bg.block<3, 3>(0, 0) -= Jl.C_t;
  s.H_bg = H_bg;

  s.xi.segment<3>(3) += dt * s.xi.segment<3>(6) + h * a_start;
  s.xi.segment<3>(6) += dt * a_start;
  s.xi.segment<3>(0) += dt * w_tangent;
  s.dt += dt;

  if constexpr (kJacobians) *J = Jl;
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
  const std::size_t K = w.size();
  for (std::size_t j = 0; j < K; ++j) {
    const ImuSample& s = w[j];
    if (!std::isfinite(s.t) || !s.gyro.allFinite() || !s.accel.allFinite())
      return Status::Error("knot " + std::to_string(j) + " of the window is not finite");
    if (j > 0 && !(s.t > w[j - 1].t))
      return Status::Error("knot times must increase strictly (knot " + std::to_string(j) + ")");
  }
  return Status::Ok();
}

/// Runs a step function over the window with zero-order hold: knot j, bias-corrected with
/// (bg, ba), held over [t_j, t_j+1]. Step(acc, omega, dt, increment, J*) and, if
/// kCovariance, the combined covariance.
template <bool kCovariance, typename Increment, typename StepFn>
inline void RunZeroOrderHold(const PreintegrationInput& in, StepFn step, Increment& inc, CombinedCovariance* cov) {
  const SampleWindow& w = in.window;
  const NoiseVariances q = NoiseVariances::FromDensities(in.noise);
  const std::size_t K = w.size();
  StepJacobians J;
  for (std::size_t j = 0; j + 1 < K; ++j) {
    const ImuSample& s = w[j];
    const double dt = w[j + 1].t - s.t;
    const Vec3 acc = s.accel - in.ba;
    const Vec3 omega = s.gyro - in.bg;
    if constexpr (kCovariance) {
      step(acc, omega, dt, inc, &J);
      PropagateCombined(J, q, *cov);
    } else {
      step(acc, omega, dt, inc, nullptr);
    }
  }
}

/// Manifold scheme over the window; covariance in the NavState chart ("gtsam_manifold"),
/// bias Jacobian in dR Exp(dtheta), additive dp, dv ("gtsam_manifold_jacobian").
template <bool kCovariance = true>
inline Status IntegrateManifold(const PreintegrationInput& in, NativePreintegration& out,
                                ManifoldIncrement* increment = nullptr) {
  Status st = CheckPreintegrationInput(in);
  if (!st.ok()) return st;
  ManifoldIncrement inc;
  CombinedCovariance cov;
  RunZeroOrderHold<kCovariance>(
      in, [](const Vec3& a, const Vec3& w, double dt, ManifoldIncrement& s, StepJacobians* J) {
        if constexpr (kCovariance) ManifoldStep<true>(a, w, dt, s, J);
        else ManifoldStep<false>(a, w, dt, s, J);
      }, inc, &cov);
  out.dt = inc.dt;
  out.delta.dR = inc.dR;
  out.delta.dp = inc.dp;
  out.delta.dv = inc.dv;
  out.delta.dbg.setZero();
  out.delta.dba.setZero();
  out.bg_hat = in.bg;
  out.ba_hat = in.ba;
  out.cov = kCovariance ? cov.Assemble() : Mat15::Zero();
  out.J_bias = inc.BiasJacobian();
  if (increment) *increment = inc;
  return Status::Ok();
}

/// Tangent scheme over the window; covariance and bias Jacobian additive on the tangent
/// 9-vector ("gtsam_tangent").
template <bool kCovariance = true>
inline Status IntegrateTangent(const PreintegrationInput& in, NativePreintegration& out,
                               TangentIncrement* increment = nullptr) {
  Status st = CheckPreintegrationInput(in);
  if (!st.ok()) return st;
  TangentIncrement inc;
  CombinedCovariance cov;
  RunZeroOrderHold<kCovariance>(
      in, [](const Vec3& a, const Vec3& w, double dt, TangentIncrement& s, StepJacobians* J) {
        if constexpr (kCovariance) TangentStep<true>(a, w, dt, s, J);
        else TangentStep<false>(a, w, dt, s, J);
      }, inc, &cov);
  out.dt = inc.dt;
  out.delta.dR = so3::Exp(inc.xi.segment<3>(0));
  out.delta.dp = inc.xi.segment<3>(3);
  out.delta.dv = inc.xi.segment<3>(6);
  out.delta.dbg.setZero();
  out.delta.dba.setZero();
  out.bg_hat = in.bg;
  out.ba_hat = in.ba;
  out.cov = kCovariance ? cov.Assemble() : Mat15::Zero();
  out.J_bias = inc.BiasJacobian();
  if (increment) *increment = inc;
  return Status::Ok();
}

}  // namespace imuconv::kernels
