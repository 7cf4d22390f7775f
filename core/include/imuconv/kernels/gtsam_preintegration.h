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
// has Jacobians in GTSAM's notation,
//   A = d x' / d x (9x9),  B = d x' / d acc (9x3),  C = d x' / d omega (9x3),
// which drive both the bias Jacobians (inputs move by minus the bias change)
//   H_ba' = A H_ba - B,   H_bg' = A H_bg - C,
// and the covariance of the 15-state [theta, p, v, ba, bg] (GTSAM's preintMeasCov order):
//   F = [A  Fb; 0  I6],  Fb = [0 C_theta; B_p 0; B_v 0],
//   Sigma' = F Sigma F^T + diag(B (s_a^2/dt) B^T + C (s_g^2/dt) C^T,  dt q_a^2 I, dt q_g^2 I),
// (s_a, s_g: white-noise densities; q_a, q_g: random-walk densities; GTSAM's
// integrationCovariance and biasAccOmegaInit are zero), i.e. the first-order discrete
// propagation of the paper's section 2.1 with the bias random walk Delta b (eq. preint-b)
// appended. The bias error state of that covariance is delta b = -Delta b (paper, "GTSAM
// Peculiarities", eq. preint-error-db), which is why Fb enters with the sign of
// d x'/d(acc, omega) rather than of d x'/d(bias).
//
// Charts of the recursion. p and v errors are additive in the start frame for both
// schemes. Every step then has the pattern
//   A = [A_tt 0 0; K dt/2  I  I dt; K  0  I],  B = [0; N dt^2/2; N dt],  C = [C_t; 0; 0]
// with N a rotation (StepJacobians below).
//   manifold: the rotation error is taken in the START frame, Exp(phi) dR. Then
//             A_tt = I exactly and K = -dt [dR acc]x is a cross product, so the step has
//             no general 3x3 product in its transition at all (six of the tangent
//             scheme's eighteen remain, all against the noise maps C and N). GTSAM's
//             NavState chart (dR Exp(dth), dp + dR dp', dv + dR dv') is reached at the end
//             of the interval by the exact linear map blockdiag(dR^T, dR^T, dR^T) at the
//             estimate: the per-step Jacobians of the two charts are similar under the
//             chart change at each step, so the products telescope.
//   tangent:  additive on xi = [theta, p, v], GTSAM's own chart; A_tt is a general 3x3.
//
// The covariance step is written through the few 3-vectors it is linear in (see
// PropagateBlocks): every 3x3 product is one of the step's maps applied to a 3x3 block
// of Sigma, the rest are scaled sums. Structure relied on: theta does not depend on the
// accelerometer (so cov(dtheta, dba) and d theta/d ba stay zero), and isotropic noise
// (ImuNoise holds scalar densities), which keeps the bias block of Sigma at
// t * diag(q_a^2 I, q_g^2 I), makes N N^T = I and gives C C^T in closed form.
//
// Speed. The recursion runs on 3x3 blocks held as three 4-lane columns (GCC/Clang vector
// extensions; lane 3 is padding and stays zero). The interval driver is compiled three
// times -- baseline x86-64, AVX2+FMA and AVX-512 -- and dispatched once per interval on
// the CPU it runs on, so the default build runs on any x86-64 and uses the wide units
// where present. The per-step trigonometry uses a local sin/cos (a few ulps, no libm
// call). Nothing in the per-sample loop touches the heap.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "imuconv/kernels/common.h"
#include "imuconv/preintegrator.h"
#include "imuconv/so3.h"
#include "imuconv/status.h"
#include "imuconv/types.h"
#include "imuconv/window.h"

#if !defined(__GNUC__)
#error "imuconv/kernels/gtsam_preintegration.h needs GCC or Clang vector extensions"
#endif

#if defined(__x86_64__)
#define IMUCONV_PREINT_X86_DISPATCH 1
#else
#define IMUCONV_PREINT_X86_DISPATCH 0
#endif

#define IMUCONV_PREINT_INLINE inline __attribute__((always_inline))

// 4-lane double vectors passed by value between always-inline helpers change no ABI.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace imuconv::kernels {

using Mat93 = Eigen::Matrix<double, 9, 3>;

namespace simd {
/// 4 doubles (GCC/Clang vector extension); 3-vectors use lanes 0-2 and keep lane 3 zero.
typedef double d4 __attribute__((vector_size(32)));
}  // namespace simd

// ---------------------------------------------------------------------------------------
// SO(3) coefficients, each set from one sin/cos evaluation.

namespace detail {

/// sin and cos of x >= 0, to a few ulps: x - n pi/2 by a three-part Cody-Waite reduction
/// (n pi/2 exact for n < 2^20), then the Taylor series of sin and cos on |r| <= pi/4 to
/// r^17 and r^16 (truncation < 1e-18 relative). Falls back to libm for huge x.
inline void SinCosNonNegative(double x, double& s, double& c) {
  if (!(x < 1.0e5)) {
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  constexpr double kTwoOverPi = 0.6366197723675814;
  constexpr double kPio2Hi = 1.5707963267341256;      // 33 significant bits
  constexpr double kPio2Mid = 6.077100506303966e-11;  // next 33 bits
  constexpr double kPio2Lo = 2.0222662487959506e-21;  // the rest, rounded
  const std::int64_t n = static_cast<std::int64_t>(x * kTwoOverPi + 0.5);
  const double nf = static_cast<double>(n);
  const double r = ((x - nf * kPio2Hi) - nf * kPio2Mid) - nf * kPio2Lo;
  const double r2 = r * r;
  constexpr double f3 = 1.0 / 6.0, f5 = f3 / 20.0, f7 = f5 / 42.0, f9 = f7 / 72.0, f11 = f9 / 110.0,
                   f13 = f11 / 156.0, f15 = f13 / 210.0, f17 = f15 / 272.0;
  constexpr double f2 = 0.5, f4 = f2 / 12.0, f6 = f4 / 30.0, f8 = f6 / 56.0, f10 = f8 / 90.0, f12 = f10 / 132.0,
                   f14 = f12 / 182.0, f16 = f14 / 240.0;
  const double ps =
      r + r * r2 * (-f3 + r2 * (f5 + r2 * (-f7 + r2 * (f9 + r2 * (-f11 + r2 * (f13 + r2 * (-f15 + r2 * f17)))))));
  const double pc =
      1.0 + r2 * (-f2 + r2 * (f4 + r2 * (-f6 + r2 * (f8 + r2 * (-f10 + r2 * (f12 + r2 * (-f14 + r2 * f16)))))));
  switch (n & 3) {
    case 0: s = ps, c = pc; break;
    case 1: s = pc, c = -ps; break;
    case 2: s = -ps, c = -pc; break;
    default: s = -pc, c = ps; break;
  }
}

/// Below this |theta| the tangent scheme's coefficients come from their power series in
/// t^2 (no sqrt, sin/cos or division): d(t) = 1/t^2 - cot(t/2)/(2t), the [phi]x^2
/// coefficient of Jr^{-1}, is sum_{n>=1} |B_2n|/(2n)! t^(2n-2) (Bernoulli numbers, from the
/// Laurent series of cot; radius 2 pi), e(t) = d'(t)/t = sum_{n>=2} (2n-2)|B_2n|/(2n)!
/// t^(2n-4), and sin t/t, (1 - cos t)/t^2, (t - sin t)/t^3 are alternating Taylor series.
/// At t = 2 successive Bernoulli terms shrink by (2/(2 pi))^2 < 0.102: 18 terms of d and
/// 20 of e leave < 2e-17 relative, as do 20 of the others (the coefficients below are the
/// exact rationals rounded to double).
constexpr double kTangentSeriesBelow = 2.0;

/// d(t) from x = t^2 < 4 by Estrin's scheme (five FMA levels deep): the tangent scheme's
/// theta' = theta + dt Jr^{-1}(theta) omega needs only d, so this is the whole loop-carried
/// path of the recursion.
IMUCONV_PREINT_INLINE double JrInvSeriesD(double x) {
  constexpr double c[18] = {0.08333333333333333, 0.001388888888888889, 3.306878306878307e-05, 8.267195767195768e-07, 2.08767569878681e-08, 5.284190138687493e-10, 1.3382536530684679e-11, 3.3896802963225827e-13, 8.586062056277845e-15, 2.174868698558062e-16, 5.5090028283602295e-18, 1.3954464685812522e-19, 3.534707039629467e-21, 8.953517427037546e-23, 2.267952452337683e-24, 5.744790668872202e-26, 1.455172475614865e-27, 3.6859949406653103e-29};
  const double x2 = x * x, x4 = x2 * x2, x8 = x4 * x4, x16 = x8 * x8;
  const double q0 = c[0] + c[1] * x, q1 = c[2] + c[3] * x, q2 = c[4] + c[5] * x, q3 = c[6] + c[7] * x;
  const double q4 = c[8] + c[9] * x, q5 = c[10] + c[11] * x, q6 = c[12] + c[13] * x, q7 = c[14] + c[15] * x;
  const double q8 = c[16] + c[17] * x;
  const double r0 = q0 + q1 * x2, r1 = q2 + q3 * x2, r2 = q4 + q5 * x2, r3 = q6 + q7 * x2;
  return ((r0 + r1 * x4) + (r2 + r3 * x4) * x8) + q8 * x16;
}

/// (sin t/t, (1 - cos t)/t^2, (t - sin t)/t^3, e(t)) from x = t^2 < 4, as one 4-lane
/// polynomial.
IMUCONV_PREINT_INLINE simd::d4 TangentSeriesABCE(double x) {
  static constexpr simd::d4 c[20] = {
    {1.0, 0.5, 0.16666666666666666, 0.002777777777777778},
    {-0.16666666666666666, -0.041666666666666664, -0.008333333333333333, 0.00013227513227513228},
    {0.008333333333333333, 0.001388888888888889, 0.0001984126984126984, 4.96031746031746e-06},
    {-0.0001984126984126984, -2.48015873015873e-05, -2.7557319223985893e-06, 1.670140559029448e-07},
    {2.7557319223985893e-06, 2.755731922398589e-07, 2.505210838544172e-08, 5.2841901386874934e-09},
    {-2.505210838544172e-08, -2.08767569878681e-09, -1.6059043836821613e-10, 1.6059043836821613e-10},
    {1.6059043836821613e-10, 1.1470745597729725e-11, 7.647163731819816e-13, 4.745552414851616e-12},
    {-7.647163731819816e-13, -4.779477332387385e-14, -2.8114572543455206e-15, 1.3737699290044552e-13},
    {2.8114572543455206e-15, 1.5619206968586225e-16, 8.22063524662433e-18, 3.914763657404511e-15},
    {-8.22063524662433e-18, -4.110317623312165e-19, -1.9572941063391263e-20, 1.1018005656720459e-16},
    {1.9572941063391263e-20, 8.896791392450574e-22, 3.868170170630684e-23, 3.069982230878755e-18},
    {-3.868170170630684e-23, -1.6117375710961184e-24, -6.446950284384474e-26, 8.483296895110721e-20},
    {6.446950284384474e-26, 2.4795962632247976e-27, 9.183689863795546e-29, 2.327914531029762e-21},
    {-9.183689863795546e-29, -3.279889237069838e-30, -1.1309962886447716e-31, 6.350266866545513e-23},
    {1.1309962886447716e-31, 3.7699876288159054e-33, 1.216125041553518e-34, 1.7234372006616606e-24},
    {-1.216125041553518e-34, -3.8003907548547434e-36, -1.151633562077195e-37, 4.656551921967568e-26},
    {1.151633562077195e-37, 3.387157535521162e-39, 9.67759295863189e-41, 1.2532382798262054e-27},
    {-9.67759295863189e-41, -2.6882202662866363e-42, -7.265460179153071e-44, 3.3612243325542163e-29},
    {7.265460179153071e-44, 1.911963205040282e-45, 4.902469756513544e-47, 8.987085179662393e-31},
    {-4.902469756513544e-47, -1.2256174391283858e-48, -2.9893108271424046e-50, 2.3962687049928537e-32},
  };
  // Estrin's scheme (six FMA levels deep rather than Horner's nineteen: this sits on the
  // step's critical path, theta -> coefficients -> maps -> products).
  const simd::d4 x0 = {x, 0.0, 0.0, 0.0}, v = __builtin_shufflevector(x0, x0, 0, 0, 0, 0);
  const simd::d4 v2 = v * v, v4 = v2 * v2, v8 = v4 * v4, v16 = v8 * v8;
  simd::d4 q[10];
  for (int k = 0; k < 10; ++k) q[k] = c[2 * k] + c[2 * k + 1] * v;
  const simd::d4 r0 = q[0] + q[1] * v2, r1 = q[2] + q[3] * v2, r2 = q[4] + q[5] * v2, r3 = q[6] + q[7] * v2,
                 r4 = q[8] + q[9] * v2;
  return ((r0 + r1 * v4) + (r2 + r3 * v4) * v8) + r4 * v16;
}

/// Coefficients of Exp = I + a S + b S^2, Jr = I - b S + c S^2 (S = [phi]x, t = |phi|).
struct ExpJrCoefs {
  double a, b, c;
};

/// Below so3::detail::kSeriesBelow: the series of so3.h (in t^2 only, truncation < 1e-17),
/// with the divisions by constants as multiplications.
IMUCONV_PREINT_INLINE ExpJrCoefs ExpJrSeries(double t2) {
  constexpr double r6 = 1.0 / 6.0, r20 = 1.0 / 20.0, r42 = 1.0 / 42.0, r72 = 1.0 / 72.0, r12 = 1.0 / 12.0,
                   r30 = 1.0 / 30.0, r56 = 1.0 / 56.0, r90 = 1.0 / 90.0, r110 = 1.0 / 110.0;
  return {1.0 - t2 * r6 * (1.0 - t2 * r20 * (1.0 - t2 * r42 * (1.0 - t2 * r72))),
          0.5 * (1.0 - t2 * r12 * (1.0 - t2 * r30 * (1.0 - t2 * r56 * (1.0 - t2 * r90)))),
          r6 * (1.0 - t2 * r20 * (1.0 - t2 * r42 * (1.0 - t2 * r72 * (1.0 - t2 * r110))))};
}
IMUCONV_PREINT_INLINE double JrInvSeries(double t2) {
  constexpr double c1 = 1.0 / 12.0, c2 = 1.0 / 720.0, c3 = 1.0 / 30240.0, c4 = 1.0 / 1209600.0;
  return c1 + t2 * (c2 + t2 * (c3 + t2 * c4));
}

/// Closed forms from sin/cos of the half angle: sin t = 2 sh ch, 1 - cos t = 2 sh^2.
IMUCONV_PREINT_INLINE ExpJrCoefs ExpJrClosed(double t, double inv_t2, double sh, double ch) {
  const double sin_t = 2.0 * sh * ch, inv_t = t * inv_t2;
  return {sin_t * inv_t, 2.0 * sh * sh * inv_t2, (t - sin_t) * inv_t2 * inv_t};
}

inline ExpJrCoefs ComputeExpJrCoefs(double t, double t2) {
  if (t < so3::detail::kSeriesBelow) return ExpJrSeries(t2);  // no trig
  double sh, ch;
  SinCosNonNegative(0.5 * t, sh, ch);
  return ExpJrClosed(t, 1.0 / t2, sh, ch);
}

/// ... plus Jr^{-1} = I + S/2 + d S^2 and e = d'(t)/t, for the tangent scheme.
struct TangentCoefs {
  double a, b, c, d, e;
};
/// Closed forms, for |theta| >= kTangentSeriesBelow.
inline TangentCoefs TangentClosed(double t, double t2) {
  double sh, ch;
  SinCosNonNegative(0.5 * t, sh, ch);
  const double inv_t2 = 1.0 / t2, inv_sh = 1.0 / sh;
  const ExpJrCoefs m = ExpJrClosed(t, inv_t2, sh, ch);
  TangentCoefs k{m.a, m.b, m.c, 0.0, 0.0};
  k.d = inv_t2 - 0.5 * ch * inv_sh * (t * inv_t2);  // cot(t/2) = cos/sin of the half angle
  k.e = (0.25 * inv_sh * inv_sh - inv_t2 - k.d) * inv_t2;
  return k;
}

IMUCONV_PREINT_INLINE TangentCoefs ComputeTangentCoefs(double t, double t2) {
  if (!(t < kTangentSeriesBelow)) return TangentClosed(t, t2);
  const simd::d4 abce = TangentSeriesABCE(t2);
  return {abce[0], abce[1], abce[2], JrInvSeriesD(t2), abce[3]};
}

/// C C^T for C = dt (I + beta S + delta S^2) with S skew (Jl, Jr, Jr^{-1} and their
/// rotations): (I + beta S + delta S^2)(I - beta S + delta S^2) = I + g S^2 with
/// g = 2 delta - beta^2 - delta^2 t^2 (S^3 = -t^2 S), so C C^T = dt^2 (I + g [u]x^2).
IMUCONV_PREINT_INLINE double SymmetricSquareCoef(double beta, double delta, double t2) {
  return 2.0 * delta - beta * beta - delta * delta * t2;
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
// Increments, and one step of each scheme with its Jacobians in plain Eigen: the
// specification the block recursion below implements (the tests difference these steps
// and run the dense 15x15 recursion from their Jacobians).

/// A, B, C of one step in the kernel's chart:
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

/// Increment of the manifold scheme.
struct ManifoldIncrement {
  double dt = 0.0;
  Mat3 dR = Mat3::Identity();
  Vec3 dp = Vec3::Zero(), dv = Vec3::Zero();
};

/// One zero-order-hold step of the manifold scheme with bias-corrected inputs
/// acc = a_m - ba_hat, omega = w_m - bg_hat held over dt:
///   dp' = dp + dv dt + dR acc dt^2/2,  dv' = dv + dR acc dt,  dR' = dR Exp(omega dt).
/// Jacobians in the start-frame chart (Exp(phi) dR, dp + ddp, dv + ddv), with dR the
/// rotation before the step:
///   A_tt = I,  K = -dt [dR acc]x,  N = dR,  C_t = dR Jl(omega dt) dt
/// (Exp(phi) dR Exp(omega dt + dt domega) = Exp(phi + dR Exp(omega dt) Jr(omega dt) dt
/// domega) dR' to first order, and Exp(w) Jr(w) = Jl(w)).
inline void ManifoldStep(const Vec3& acc, const Vec3& omega, double dt, ManifoldIncrement& s, StepJacobians& J) {
  const double h = 0.5 * dt * dt;
  const Vec3 phi = omega * dt;
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const detail::ExpJrCoefs k = detail::ComputeExpJrCoefs(t, t2);
  const Mat3 S = so3::skew(phi), S2 = S * S;
  const Mat3 E = Mat3::Identity() + k.a * S + k.b * S2;
  const Mat3 Jl = Mat3::Identity() + k.b * S + k.c * S2;
  const Vec3 a_start = s.dR * acc;  // acceleration in the start frame

  J.dt = dt;
  J.A_tt.setIdentity();
  J.K = (-dt) * so3::skew(a_start);
  J.N = s.dR;
  J.C_t = dt * (s.dR * Jl);

  s.dp += dt * s.dv + h * a_start;
  s.dv += dt * a_start;
  s.dR = s.dR * E;
  s.dt += dt;
}

/// Increment of the tangent scheme: xi = [theta, p, v] with dR = Exp(theta).
struct TangentIncrement {
  double dt = 0.0;
  Vec9 xi = Vec9::Zero();
};

/// One zero-order-hold step of the tangent scheme, with R = Exp(theta):
///   theta' = theta + Jr^{-1}(theta) omega dt,
///   p' = p + v dt + R acc dt^2/2,  v' = v + R acc dt.
/// Exact Jacobians in the additive chart of xi, with d(R acc)/dtheta = -R [acc]x Jr(theta)
/// = -[R acc]x Jl(theta):
///   A_tt = I + d(Jr^{-1}(theta) omega)/dtheta dt,  K = -[R acc]x Jl(theta) dt,
///   N = R,  C_t = Jr^{-1}(theta) dt.
inline void TangentStep(const Vec3& acc, const Vec3& omega, double dt, TangentIncrement& s, StepJacobians& J) {
  const double h = 0.5 * dt * dt;
  const Vec3 theta = s.xi.segment<3>(0);
  const double t2 = theta.squaredNorm(), t = std::sqrt(t2);
  const detail::TangentCoefs k = detail::ComputeTangentCoefs(t, t2);
  const Mat3 S = so3::skew(theta), S2 = S * S;
  const Mat3 R = Mat3::Identity() + k.a * S + k.b * S2;
  const Mat3 Jl = Mat3::Identity() + k.b * S + k.c * S2;
  const Mat3 JrInv = Mat3::Identity() + 0.5 * S + k.d * S2;
  const Vec3 a_start = R * acc;

  J.dt = dt;
  J.A_tt = Mat3::Identity() + dt * detail::JrInvTimesVecDerivative(theta, omega, k.d, k.e);
  J.K = (-dt) * so3::skew(a_start) * Jl;
  J.N = R;
  J.C_t = dt * JrInv;

  s.xi.segment<3>(3) += dt * s.xi.segment<3>(6) + h * a_start;
  s.xi.segment<3>(6) += dt * a_start;
  s.xi.segment<3>(0) += dt * (JrInv * omega);
  s.dt += dt;
}

// Discrete noise: kernels::NoiseVariances (common.h) holds the densities squared; white
// noise is divided by dt per step, the bias random walks multiplied by dt. GTSAM's
// integrationCovariance and biasAccOmegaInit are zero here.

// ---------------------------------------------------------------------------------------
// 3x3 blocks as three 4-lane columns, and pairs of blocks side by side.

namespace simd {

/// Column-major 3x3 block; lane 3 of every column is zero.
struct B {
  d4 c[3];
};

/// x in every lane. Written as a shuffle of lane 0: GCC 12 emits the plain initializer
/// {x, x, x, x} of a register as two instructions under the target attribute, this as one
/// vbroadcastsd (from memory when x is a load).
IMUCONV_PREINT_INLINE d4 Splat(double x) {
  const d4 v = {x, 0.0, 0.0, 0.0};
  return __builtin_shufflevector(v, v, 0, 0, 0, 0);
}
/// Lane k of v in every lane (one permute; Splat(v[k]) when v is in memory).
template <int k>
IMUCONV_PREINT_INLINE d4 Lane(const d4& v) {
  return __builtin_shufflevector(v, v, k, k, k, k);
}
IMUCONV_PREINT_INLINE d4 Load3(const double* p) { return d4{p[0], p[1], p[2], 0.0}; }
IMUCONV_PREINT_INLINE d4 FromEigen(const Vec3& v) { return Load3(v.data()); }
IMUCONV_PREINT_INLINE Vec3 ToEigen(const d4& v) { return Vec3(v[0], v[1], v[2]); }
IMUCONV_PREINT_INLINE void ToEigen(const B& m, Eigen::Ref<Eigen::Matrix<double, 3, 3>, 0, Eigen::OuterStride<>> out) {
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) out(i, j) = m.c[j][i];
}

constexpr d4 kE0 = {1.0, 0.0, 0.0, 0.0}, kE1 = {0.0, 1.0, 0.0, 0.0}, kE2 = {0.0, 0.0, 1.0, 0.0};
IMUCONV_PREINT_INLINE B Identity() { return {{kE0, kE1, kE2}}; }
IMUCONV_PREINT_INLINE B Zero() { return {{Splat(0.0), Splat(0.0), Splat(0.0)}}; }

IMUCONV_PREINT_INLINE B operator+(const B& a, const B& b) { return {{a.c[0] + b.c[0], a.c[1] + b.c[1], a.c[2] + b.c[2]}}; }
IMUCONV_PREINT_INLINE B operator-(const B& a, const B& b) { return {{a.c[0] - b.c[0], a.c[1] - b.c[1], a.c[2] - b.c[2]}}; }
IMUCONV_PREINT_INLINE B operator*(double s, const B& a) {
  const d4 v = Splat(s);
  return {{v * a.c[0], v * a.c[1], v * a.c[2]}};
}
/// a + s b.
IMUCONV_PREINT_INLINE B AddScaled(const B& a, double s, const B& b) {
  const d4 v = Splat(s);
  return {{a.c[0] + v * b.c[0], a.c[1] + v * b.c[1], a.c[2] + v * b.c[2]}};
}
/// a + s I.
IMUCONV_PREINT_INLINE B AddDiagonal(const B& a, double s) {
  const d4 v = Splat(s);
  return {{a.c[0] + v * kE0, a.c[1] + v * kE1, a.c[2] + v * kE2}};
}
IMUCONV_PREINT_INLINE B Transpose(const B& a) {
  const d4 lo = __builtin_shufflevector(a.c[0], a.c[1], 0, 4, 2, 6);  // a00 a01 a20 a21
  const d4 hi = __builtin_shufflevector(a.c[0], a.c[1], 1, 5, 3, 7);  // a10 a11 0 0
  return {{__builtin_shufflevector(lo, a.c[2], 0, 1, 4, 7), __builtin_shufflevector(hi, a.c[2], 0, 1, 5, 7),
           __builtin_shufflevector(lo, a.c[2], 2, 3, 6, 7)}};
}

// Products broadcast the entries of one factor and scale the columns of the other; the
// broadcast factor should sit in memory (state blocks, or InMemory below), so that the
// broadcasts are loads. The *Add forms accumulate into acc (FMAs only).
/// acc + a b.
IMUCONV_PREINT_INLINE B MulAdd(const B& acc, const B& a, const B& b) {
  B r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = acc.c[j] + a.c[0] * Splat(b.c[j][0]) + a.c[1] * Splat(b.c[j][1]) + a.c[2] * Splat(b.c[j][2]);
  return r;
}
/// a b.
IMUCONV_PREINT_INLINE B Mul(const B& a, const B& b) {
  B r;
  for (int j = 0; j < 3; ++j) r.c[j] = a.c[0] * Splat(b.c[j][0]) + a.c[1] * Splat(b.c[j][1]) + a.c[2] * Splat(b.c[j][2]);
  return r;
}
/// acc + a b^T.
IMUCONV_PREINT_INLINE B MulTAdd(const B& acc, const B& a, const B& b) {
  B r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = acc.c[j] + a.c[0] * Splat(b.c[0][j]) + a.c[1] * Splat(b.c[1][j]) + a.c[2] * Splat(b.c[2][j]);
  return r;
}
/// a b^T.
IMUCONV_PREINT_INLINE B MulT(const B& a, const B& b) {
  B r;
  for (int j = 0; j < 3; ++j) r.c[j] = a.c[0] * Splat(b.c[0][j]) + a.c[1] * Splat(b.c[1][j]) + a.c[2] * Splat(b.c[2][j]);
  return r;
}
/// a v (v in a register: lane permutes).
IMUCONV_PREINT_INLINE d4 MulV(const B& a, const d4& v) { return a.c[0] * Lane<0>(v) + a.c[1] * Lane<1>(v) + a.c[2] * Lane<2>(v); }

IMUCONV_PREINT_INLINE d4 Yzx(const d4& a) { return __builtin_shufflevector(a, a, 1, 2, 0, 3); }
IMUCONV_PREINT_INLINE double Dot(const d4& a, const d4& b) {
  const d4 p = a * b;
  return p[0] + p[1] + p[2];
}
/// a x b.
IMUCONV_PREINT_INLINE d4 Cross(const d4& a, const d4& b) { return Yzx(a * Yzx(b) - Yzx(a) * b); }
/// z [b]x, with b's entries broadcast in b0, b1, b2.
IMUCONV_PREINT_INLINE B TimesSkew(const B& z, const d4& b0, const d4& b1, const d4& b2) {
  return {{b2 * z.c[1] - b1 * z.c[2], b0 * z.c[2] - b2 * z.c[0], b1 * z.c[0] - b0 * z.c[1]}};
}
/// u v^T.
IMUCONV_PREINT_INLINE B Outer(const d4& u, const d4& v) { return {{u * Lane<0>(v), u * Lane<1>(v), u * Lane<2>(v)}}; }

/// [w]x and w w^T by columns, for alpha I + beta [w]x + gamma w w^T (Exp, Jr, Jl, Jr^{-1}
/// of w, with [w]x^2 = w w^T - |w|^2 I).
struct So3Basis {
  B skew, outer;
};
IMUCONV_PREINT_INLINE So3Basis MakeSo3Basis(const d4& w) {
  const d4 m = -w;
  return {{{__builtin_shufflevector(w, m, 3, 2, 5, 3), __builtin_shufflevector(w, m, 6, 3, 0, 3),
            __builtin_shufflevector(w, m, 1, 4, 3, 3)}},
          Outer(w, w)};
}
IMUCONV_PREINT_INLINE B Poly(const So3Basis& s, double alpha, double beta, double gamma) {
  const d4 a = Splat(alpha), b = Splat(beta), g = Splat(gamma);
  return {{a * kE0 + b * s.skew.c[0] + g * s.outer.c[0], a * kE1 + b * s.skew.c[1] + g * s.outer.c[1],
           a * kE2 + b * s.skew.c[2] + g * s.outer.c[2]}};
}

/// Makes the compiler keep `x` in memory from here on, so that broadcasts of its entries
/// are loads (load ports) instead of lane shuffles.
template <typename T>
IMUCONV_PREINT_INLINE void InMemory(T& x) {
  asm volatile("" : "+m"(x));
}

// ---- Pairs. Two 4-lane columns side by side: one 8-lane vector under AVX-512 (d8), two
// 4-lane halves elsewhere (d4x2: without AVX-512, GCC lowers 8-lane shuffles through
// memory). The kernels are written once over the pair type W.

typedef double d8 __attribute__((vector_size(64)));
struct d4x2 {
  d4 lo, hi;
};
IMUCONV_PREINT_INLINE d4x2 operator+(const d4x2& a, const d4x2& b) { return {a.lo + b.lo, a.hi + b.hi}; }
IMUCONV_PREINT_INLINE d4x2 operator-(const d4x2& a, const d4x2& b) { return {a.lo - b.lo, a.hi - b.hi}; }
IMUCONV_PREINT_INLINE d4x2 operator*(const d4x2& a, const d4x2& b) { return {a.lo * b.lo, a.hi * b.hi}; }
IMUCONV_PREINT_INLINE d4x2 operator-(const d4x2& a) { return {-a.lo, -a.hi}; }

IMUCONV_PREINT_INLINE d4 Lo(const d8& x) { return __builtin_shufflevector(x, x, 0, 1, 2, 3); }
IMUCONV_PREINT_INLINE d4 Hi(const d8& x) { return __builtin_shufflevector(x, x, 4, 5, 6, 7); }
IMUCONV_PREINT_INLINE d4 Lo(const d4x2& x) { return x.lo; }
IMUCONV_PREINT_INLINE d4 Hi(const d4x2& x) { return x.hi; }

template <class W>
struct PairOps;
template <>
struct PairOps<d8> {
  static IMUCONV_PREINT_INLINE d8 Cat(const d4& a, const d4& b) { return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7); }
  static IMUCONV_PREINT_INLINE d8 Splat(double x) {
    const d8 v = {x, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    return __builtin_shufflevector(v, v, 0, 0, 0, 0, 0, 0, 0, 0);
  }
  /// [lane k of the first half x4 | lane k of the second half x4].
  template <int k>
  static IMUCONV_PREINT_INLINE d8 Lane(const d8& x) {
    return __builtin_shufflevector(x, x, k, k, k, k, k + 4, k + 4, k + 4, k + 4);
  }
  static IMUCONV_PREINT_INLINE d8 Yzx(const d8& x) { return __builtin_shufflevector(x, x, 1, 2, 0, 3, 5, 6, 4, 7); }
  /// [second half | 0].
  static IMUCONV_PREINT_INLINE d8 ShiftDown(const d8& x) {
    const d8 z = {};
    return __builtin_shufflevector(x, z, 4, 5, 6, 7, 8, 8, 8, 8);
  }
  /// [first half of a | first half of b].
  static IMUCONV_PREINT_INLINE d8 Los(const d8& a, const d8& b) { return __builtin_shufflevector(a, b, 0, 1, 2, 3, 8, 9, 10, 11); }
  /// [second half of a | second half of a].
  static IMUCONV_PREINT_INLINE d8 DupHi(const d8& a) { return __builtin_shufflevector(a, a, 4, 5, 6, 7, 4, 5, 6, 7); }};
template <>
struct PairOps<d4x2> {
  static IMUCONV_PREINT_INLINE d4x2 Cat(const d4& a, const d4& b) { return {a, b}; }
  static IMUCONV_PREINT_INLINE d4x2 Splat(double x) {
    const d4 v = simd::Splat(x);
    return {v, v};
  }
  template <int k>
  static IMUCONV_PREINT_INLINE d4x2 Lane(const d4x2& x) {
    return {simd::Lane<k>(x.lo), simd::Lane<k>(x.hi)};
  }
  static IMUCONV_PREINT_INLINE d4x2 Yzx(const d4x2& x) { return {simd::Yzx(x.lo), simd::Yzx(x.hi)}; }
  static IMUCONV_PREINT_INLINE d4x2 ShiftDown(const d4x2& x) { return {x.hi, d4{}}; }
  static IMUCONV_PREINT_INLINE d4x2 Los(const d4x2& a, const d4x2& b) { return {a.lo, b.lo}; }
  static IMUCONV_PREINT_INLINE d4x2 DupHi(const d4x2& a) { return {a.hi, a.hi}; }
};

/// Two 3x3 blocks side by side: column j is [column j of the first | of the second].
template <class W>
struct BB {
  W c[3];
};

template <class W>
IMUCONV_PREINT_INLINE B Lo(const BB<W>& x) {
  return {{Lo(x.c[0]), Lo(x.c[1]), Lo(x.c[2])}};
}
template <class W>
IMUCONV_PREINT_INLINE B Hi(const BB<W>& x) {
  return {{Hi(x.c[0]), Hi(x.c[1]), Hi(x.c[2])}};
}
template <class W>
IMUCONV_PREINT_INLINE BB<W> Pair(const B& a, const B& b) {
  using O = PairOps<W>;
  return {{O::Cat(a.c[0], b.c[0]), O::Cat(a.c[1], b.c[1]), O::Cat(a.c[2], b.c[2])}};
}
template <class W>
IMUCONV_PREINT_INLINE BB<W> operator+(const BB<W>& a, const BB<W>& b) {
  return {{a.c[0] + b.c[0], a.c[1] + b.c[1], a.c[2] + b.c[2]}};
}
/// a + s b with s one scalar or [s1 | s2] per half.
template <class W>
IMUCONV_PREINT_INLINE BB<W> AddScaled(const BB<W>& a, const W& s, const BB<W>& b) {
  return {{a.c[0] + s * b.c[0], a.c[1] + s * b.c[1], a.c[2] + s * b.c[2]}};
}
/// [a1 b^T | a2 b^T] accumulated into acc (b's entries broadcast over both halves).
template <class W>
IMUCONV_PREINT_INLINE BB<W> MulTAdd(const BB<W>& acc, const BB<W>& a, const B& b) {
  using O = PairOps<W>;
  BB<W> r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = acc.c[j] + a.c[0] * O::Splat(b.c[0][j]) + a.c[1] * O::Splat(b.c[1][j]) + a.c[2] * O::Splat(b.c[2][j]);
  return r;
}
template <class W>
IMUCONV_PREINT_INLINE BB<W> MulT(const BB<W>& a, const B& b) {
  using O = PairOps<W>;
  BB<W> r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = a.c[0] * O::Splat(b.c[0][j]) + a.c[1] * O::Splat(b.c[1][j]) + a.c[2] * O::Splat(b.c[2][j]);
  return r;
}
/// [l1 b | l2 b]: the two blocks of l times the same b (b's entries broadcast).
template <class W>
IMUCONV_PREINT_INLINE BB<W> MulPair(const BB<W>& l, const B& b) {
  using O = PairOps<W>;
  BB<W> r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = l.c[0] * O::Splat(b.c[j][0]) + l.c[1] * O::Splat(b.c[j][1]) + l.c[2] * O::Splat(b.c[j][2]);
  return r;
}
/// [m z1 | m z2] for dm = [m | m]: one m times the two blocks of z.
template <class W>
IMUCONV_PREINT_INLINE BB<W> MulDup(const BB<W>& dm, const BB<W>& z) {
  using O = PairOps<W>;
  BB<W> r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = dm.c[0] * O::template Lane<0>(z.c[j]) + dm.c[1] * O::template Lane<1>(z.c[j]) +
             dm.c[2] * O::template Lane<2>(z.c[j]);
  return r;
}
/// [z1 [b]x | z2 [b]x].
template <class W>
IMUCONV_PREINT_INLINE BB<W> TimesSkew(const BB<W>& z, const W& b0, const W& b1, const W& b2) {
  return {{b2 * z.c[1] - b1 * z.c[2], b0 * z.c[2] - b2 * z.c[0], b1 * z.c[0] - b0 * z.c[1]}};
}

}  // namespace simd

// ---------------------------------------------------------------------------------------
// The block recursion shared by both schemes.

namespace detail {

using simd::B;
using simd::BB;
using simd::d4;

/// The recursion's state, in 3x3 blocks (W: the pair type of the instance):
///   P = cov(delta x9) by its lower blocks (cov(row, column) for rows/columns theta, p, v),
///       column theta's p and v blocks side by side;
///   X = cov(delta x9, delta b), bias columns a (ba) and g (bg); the theta rows of the a
///       columns stay zero (theta does not see the accelerometer);
///   H = d x9 / d(ba, bg), same block pattern as X;
///   S = diag(s_ba I3, s_bg I3): with isotropic random walks and zero initial bias
///       uncertainty the bias block is exactly the accumulated random walk.
/// X and H follow the same recursion (X' = A X + Fb S, H' = A H - Fb) and are kept side
/// by side, [X_rc | H_rc] for row block r and bias column c.
template <class W>
struct State {
  B Ptt;
  BB<W> Ppvt;  ///< [Ppt | Pvt]
  B Ppp, Pvp, Pvv;
  BB<W> tg, pg, vg, pa, va;  ///< [X | H] blocks
  double s_ba, s_bg;
};

/// The state in plain blocks, as the interval drivers return it.
struct Blocks {
  B Ptt, Ppt, Pvt, Ppp, Pvp, Pvv;
  B Xpa, Xva, Xtg, Xpg, Xvg;
  B Hpa, Hva, Htg, Hpg, Hvg;
  double s_ba, s_bg;
};

template <class W>
IMUCONV_PREINT_INLINE Blocks ToBlocks(const State<W>& s) {
  using simd::Hi;
  using simd::Lo;
  return {s.Ptt,     Lo(s.Ppvt), Hi(s.Ppvt), s.Ppp,     s.Pvp,     s.Pvv,     Lo(s.pa), Lo(s.va), Lo(s.tg),
          Lo(s.pg),  Lo(s.vg),   Hi(s.pa),   Hi(s.va),  Hi(s.tg),  Hi(s.pg),  Hi(s.vg), s.s_ba,   s.s_bg};
}

template <class W>
IMUCONV_PREINT_INLINE void ZeroState(State<W>& s) {
  const B z = simd::Zero();
  const BB<W> zz = simd::Pair<W>(z, z);
  s = State<W>{z, zz, z, z, z, zz, zz, zz, zz, zz, 0.0, 0.0};
}

/// Everything one step broadcasts, kept in memory (InMemory) so that the broadcasts are
/// loads: the maps N, C = C_t and dt N with [N | N] and [C | C]; C C^T = dt^2 (I + cc_g
/// [cc_u]x^2) in closed form; the step's scalars; b = dt R acc for the manifold chart.
template <class W>
struct StepConsts {
  B N, C, dtN;
  BB<W> dN, dC;
  d4 cc_u, b;
  double dt, hd, h, hd2, dt2, neg_dt, neg_h, one, neg_one;
  double s_bg, hs_ba, dts_ba;                   // random-walk variances scaled
  double gg_outer, gg_diag;                     // cov(g, g) = gg_diag I + gg_outer u u^T
  double h2kw, dthkw, dt2kw;                    // cov(w, w) entering p'p', v'p', v'v'
  double s_ba_next, s_bg_next;
};

/// Fills the scalars (the maps N, C, cc_g, cc_u must be set), then pins everything in
/// memory and forms the pairs from there.
template <bool kCovariance, class W>
IMUCONV_PREINT_INLINE void FinishStepConsts(StepConsts<W>& m, double dt, double cc_g, const NoiseVariances& q,
                                            double s_ba, double s_bg) {
  m.dt = dt;
  m.hd = 0.5 * dt;
  m.h = 0.5 * dt * dt;
  m.hd2 = m.hd * m.hd;
  m.dt2 = dt * dt;
  m.neg_dt = -dt;
  m.neg_h = -m.h;
  m.one = 1.0;
  m.neg_one = -1.0;
  m.dtN = dt * m.N;
  if constexpr (kCovariance) {
    const double inv_dt = 1.0 / dt;
    const double kw = s_ba + q.accel * inv_dt;  // cov(w, w) = kw I (N is a rotation)
    const double kg = s_bg + q.gyro * inv_dt;   // cov(g, g) = kg C C^T
    const double kcc = kg * dt * dt;
    m.s_bg = s_bg;
    m.hs_ba = m.h * s_ba;
    m.dts_ba = dt * s_ba;
    m.gg_outer = kcc * cc_g;
    m.gg_diag = kcc * (1.0 - cc_g * simd::Dot(m.cc_u, m.cc_u));
    m.h2kw = m.h * m.h * kw;
    m.dthkw = dt * m.h * kw;
    m.dt2kw = dt * dt * kw;
    m.s_ba_next = s_ba + dt * q.accel_walk;
    m.s_bg_next = s_bg + dt * q.gyro_walk;
  } else {  // without the covariance X stays zero and the variances are not tracked
    m.s_bg = m.hs_ba = m.dts_ba = 0.0;
  }
  simd::InMemory(m);
  m.dN = simd::Pair<W>(m.N, m.N);
  m.dC = simd::Pair<W>(m.C, m.C);
}

/// Start-frame chart of the manifold scheme: A_tt = I, K = -[b]x with b = dt dR acc
/// (read from the step's constants in memory).
template <class W>
struct StartFrameTransition {
  static constexpr bool kGeneral = false;
  d4 b, b1;           // b and its lanes rotated (cross products)
  d4 b0s, b1s, b2s;   // b's entries broadcast
  W w0, w1, w2;       // ... over both halves
  W wb, wb1;          // [b | b], rotated
  explicit StartFrameTransition(const d4& mb) {
    using O = simd::PairOps<W>;
    b = mb;
    b1 = simd::Yzx(mb);
    b0s = simd::Splat(mb[0]);
    b1s = simd::Splat(mb[1]);
    b2s = simd::Splat(mb[2]);
    w0 = O::Splat(mb[0]);
    w1 = O::Splat(mb[1]);
    w2 = O::Splat(mb[2]);
    wb = O::Cat(mb, mb);
    wb1 = O::Yzx(wb);
  }
  /// K z = z x b, column by column.
  IMUCONV_PREINT_INLINE B LeftK(const B& z) const {
    B r;
    for (int j = 0; j < 3; ++j) r.c[j] = simd::Yzx(z.c[j] * b1 - simd::Yzx(z.c[j]) * b);
    return r;
  }
  IMUCONV_PREINT_INLINE BB<W> LeftK(const BB<W>& z) const {
    using O = simd::PairOps<W>;
    BB<W> r;
    for (int j = 0; j < 3; ++j) r.c[j] = O::Yzx(z.c[j] * wb1 - O::Yzx(z.c[j]) * wb);
    return r;
  }
  /// z A_tt^T and z K^T = z [b]x.
  IMUCONV_PREINT_INLINE void Right(const B& z, B& za, B& zk) const {
    za = z;
    zk = simd::TimesSkew(z, b0s, b1s, b2s);
  }
  IMUCONV_PREINT_INLINE void Right(const BB<W>& z, BB<W>& za, BB<W>& zk) const {
    za = z;
    zk = simd::TimesSkew(z, w0, w1, w2);
  }
  /// A_tt Yt, K Yt, K Zt: here Tt = Ptt, Ut = K Ptt, Uu = K Ptt K^T = Ut [b]x.
  IMUCONV_PREINT_INLINE void Left(const B& yt, const B&, B& tt, B& ut, B& uu) const {
    tt = yt;
    ut = LeftK(yt);
    uu = simd::TimesSkew(ut, b0s, b1s, b2s);
  }
  /// A_tt [X | H]_tg and K [X | H]_tg.
  IMUCONV_PREINT_INLINE void LeftBias(const BB<W>& z, BB<W>& az, BB<W>& kz) const {
    az = z;
    kz = LeftK(z);
  }
};

/// General A_tt and K (tangent scheme), in memory for the broadcasts, with [A | K],
/// [A | A] and [K | K] for the pair products.
template <class W>
struct GeneralTransition {
  static constexpr bool kGeneral = true;
  B A, K;
  BB<W> AK, dA, dK;
  IMUCONV_PREINT_INLINE void Right(const B& z, B& za, B& zk) const {
    za = simd::MulT(z, A);
    zk = simd::MulT(z, K);
  }
  IMUCONV_PREINT_INLINE void Right(const BB<W>& z, BB<W>& za, BB<W>& zk) const {
    za = simd::MulT(z, A);
    zk = simd::MulT(z, K);
  }
  IMUCONV_PREINT_INLINE void Left(const B& yt, const B& zt, B& tt, B& ut, B& uu) const {
    const BB<W> tu = simd::MulPair(AK, yt);  // [A Yt | K Yt]
    tt = simd::Lo(tu);
    ut = simd::Hi(tu);
    uu = simd::Mul(K, zt);
  }
  IMUCONV_PREINT_INLINE void LeftBias(const BB<W>& z, BB<W>& az, BB<W>& kz) const {
    az = simd::MulDup(dA, z);
    kz = simd::MulDup(dK, z);
  }
};

/// One step of Sigma' = F Sigma F^T + G Q G^T (see the header comment) and of the bias
/// Jacobians, from `in` to `out`, in 3x3 blocks.
///
/// The step is written through the 3-vectors it is linear in:
///   theta~ = A_tt theta,  u = K theta,  g = C_t (db_g + n_g),  w = N (db_a + n_a),
///   q = p + dt v,
///   theta' = theta~ + g,  p' = q + (dt/2) u + (dt^2/2) w,  v' = v + u + dt w,
/// so that every 3x3 product is one of the maps A_tt, K (from the left or, transposed,
/// from the right), C_t or N applied to a block. With the noise and the bias block
/// isotropic, cov(w, w) = (s_ba + s_a^2/dt) I, and g is correlated with the state only
/// through the bias columns of X; w is uncorrelated with theta (cov(dtheta, dba) = 0).
/// PreintegratedImuMeasurements' 9x9 covariance is P of this recursion run with zero
/// random walk (X and the bias block then stay zero).
template <bool kCovariance, class W, class Transition>
IMUCONV_PREINT_INLINE void PropagateBlocks(const Transition& tr, const StepConsts<W>& m, const State<W>& __restrict in,
                                           State<W>& __restrict out) {
  using namespace simd;
  using O = PairOps<W>;

  // [X | H] through the step: X' = A X + Fb S, H' = A H - Fb, with the rows of q = p + dt v
  // and of p' and v' before the inputs enter.
  BB<W> a_tg, k_tg;
  tr.LeftBias(in.tg, a_tg, k_tg);
  const BB<W> qa = AddScaled(in.pa, O::Splat(m.dt), in.va);                                  // [X | H]_qa
  const BB<W> gp = AddScaled(AddScaled(in.pg, O::Splat(m.dt), in.vg), O::Splat(m.hd), k_tg);  // q + dt/2 u vs bg
  const BB<W> gv = in.vg + k_tg;                                                               // v + u vs bg
  out.tg = AddScaled(a_tg, O::Cat(Splat(m.s_bg), Splat(m.neg_one)), m.dC);
  out.pg = gp;
  out.vg = gv;
  out.pa = AddScaled(qa, O::Cat(Splat(m.hs_ba), Splat(m.neg_h)), m.dN);
  out.va = AddScaled(in.va, O::Cat(Splat(m.dts_ba), Splat(m.neg_dt)), m.dN);
  if constexpr (!kCovariance) return;
  out.s_ba = m.s_ba_next;
  out.s_bg = m.s_bg_next;

  // Column theta of P: Yt = cov(theta, theta~), Zt = cov(theta, u), and for q and v
  // side by side; then Tt = cov(theta~, theta~), Ut = cov(u, theta~), Uu = cov(u, u).
  BB<W> Pqv;  // [cov(q, theta) | cov(v, theta)]
  for (int j = 0; j < 3; ++j) Pqv.c[j] = in.Ppvt.c[j] + O::Splat(m.dt) * O::ShiftDown(in.Ppvt.c[j]);
  B Yt, Zt, Tt, Ut, Uu;
  tr.Right(in.Ptt, Yt, Zt);
  if constexpr (Transition::kGeneral) {  // broadcast by the left products: from memory
    InMemory(Yt);
    InMemory(Zt);
  }
  tr.Left(Yt, Zt, Tt, Ut, Uu);
  InMemory(Ut);
  BB<W> Yqv, Zqv;
  tr.Right(Pqv, Yqv, Zqv);

  // cov(., g): Gt = cov(theta~, g) and [cov(q + dt/2 u, g) | cov(v + u, g)]; then P's
  // column theta. cov(g, g) = gg_diag I + gg_outer u u^T.
  {
    const B Gt = MulT(Lo(a_tg), m.C);
    const d4 gu = Splat(m.gg_outer) * m.cc_u;
    const B GG{{gu * Splat(m.cc_u[0]) + Splat(m.gg_diag) * kE0, gu * Splat(m.cc_u[1]) + Splat(m.gg_diag) * kE1,
                gu * Splat(m.cc_u[2]) + Splat(m.gg_diag) * kE2}};
    out.Ptt = Tt + Gt + Transpose(Gt) + GG;
  }
  {
    const BB<W> dUt = Pair<W>(Ut, Ut);
    const BB<W> gpv{{O::Los(gp.c[0], gv.c[0]), O::Los(gp.c[1], gv.c[1]), O::Los(gp.c[2], gv.c[2])}};
    out.Ppvt = MulTAdd(AddScaled(Yqv, O::Cat(Splat(m.hd), Splat(m.one)), dUt), gpv, m.C);
  }
  // [Rq | Sv] = [cov(q, u + dt w) | cov(v, u + dt w)] with cov(., w) = X_.a N^T; the
  // symmetric diagonal blocks are each a block plus its transpose.
  const BB<W> qva{{O::Los(qa.c[0], in.va.c[0]), O::Los(qa.c[1], in.va.c[1]), O::Los(qa.c[2], in.va.c[2])}};
  const BB<W> RS = MulTAdd(Zqv, qva, m.dtN);
  const B Rq = Lo(RS), Sv = Hi(RS);
  const B Spp = AddScaled(m.hd * Rq, m.dt, in.Pvp);
  out.Ppp = AddDiagonal(AddScaled(AddScaled(in.Ppp, m.dt2, in.Pvv), m.hd2, Uu) + Spp + Transpose(Spp), m.h2kw);
  out.Pvp = AddDiagonal(AddScaled(AddScaled(AddScaled(in.Pvp, m.dt, in.Pvv), m.hd, Sv), m.hd, Uu) + Transpose(Rq), m.dthkw);
  out.Pvv = AddDiagonal(in.Pvv + Uu + Sv + Transpose(Sv), m.dt2kw);
}

/// The held knots of the window, in order: knot j (bias-corrected with (bg, ba)) is held
/// over [t_j, t_j+1].
struct HeldKnots {
  const SampleWindow& w;
  d4 ba, bg;
  std::size_t steps() const { return w.size() - 1; }
  IMUCONV_PREINT_INLINE const ImuSample& knot(std::size_t j) const { return j == 0 ? w.first : w.samples[w.begin + j - 1]; }
  IMUCONV_PREINT_INLINE double t_next(std::size_t j) const { return j + 2 == w.size() ? w.last.t : w.samples[w.begin + j].t; }
  IMUCONV_PREINT_INLINE const ImuSample& next_knot(std::size_t j) const {
    return j + 2 == w.size() ? w.last : w.samples[w.begin + j];
  }
  /// The value held over [t_j, t_j+1]: knot j (zero-order hold, GTSAM's input) or, with
  /// kMidpoint, the mean of knots j and j+1 (OpenVINS' imu_avg; the midpoint propagator's
  /// input, see kernels/euler.h), formed in `tmp`.
  template <bool kMidpoint>
  IMUCONV_PREINT_INLINE const ImuSample& held(std::size_t j, ImuSample& tmp) const {
    if constexpr (!kMidpoint) {
      (void)tmp;
      return knot(j);
    } else {
      const ImuSample& a = knot(j);
      const ImuSample& b = next_knot(j);
      tmp.t = a.t;
      tmp.gyro = 0.5 * (a.gyro + b.gyro);
      tmp.accel = 0.5 * (a.accel + b.accel);
      return tmp;
    }
  }
};

/// Runs step(knot, dt_j, in, out) over the window, alternating the two state buffers;
/// returns the buffer holding the result.
template <class W, bool kMidpoint = false, typename StepFn>
IMUCONV_PREINT_INLINE const State<W>& RunHeldKnots(const PreintegrationInput& in, State<W>& b0, State<W>& b1,
                                                   StepFn& step) {
  const HeldKnots knots{in.window, simd::FromEigen(in.ba), simd::FromEigen(in.bg)};
  const std::size_t steps = knots.steps();
  ImuSample tmp;
  std::size_t j = 0;
  for (; j + 1 < steps; j += 2) {
    const ImuSample& s0 = knots.held<kMidpoint>(j, tmp);
    step(s0, knots.t_next(j) - s0.t, b0, b1);
    const ImuSample& s1 = knots.held<kMidpoint>(j + 1, tmp);
    step(s1, knots.t_next(j + 1) - s1.t, b1, b0);
  }
  if (j < steps) {
    const ImuSample& s0 = knots.held<kMidpoint>(j, tmp);
    step(s0, knots.t_next(j) - s0.t, b0, b1);
    return b1;
  }
  return b0;
}

/// Bias-corrected inputs of a sample, as vectors and as broadcast entries (loads from the
/// sample minus the broadcast bias).
struct Inputs {
  d4 ba[3], bg[3], ba_v, bg_v;
  explicit Inputs(const PreintegrationInput& in) {
    for (int k = 0; k < 3; ++k) {
      ba[k] = simd::Splat(in.ba[k]);
      bg[k] = simd::Splat(in.bg[k]);
    }
    ba_v = simd::FromEigen(in.ba);
    bg_v = simd::FromEigen(in.bg);
  }
  IMUCONV_PREINT_INLINE d4 acc(const ImuSample& s) const { return simd::Load3(s.accel.data()) - ba_v; }
  IMUCONV_PREINT_INLINE d4 omega(const ImuSample& s) const { return simd::Load3(s.gyro.data()) - bg_v; }
  IMUCONV_PREINT_INLINE d4 acc(const ImuSample& s, int k) const { return simd::Splat(s.accel.data()[k]) - ba[k]; }
  IMUCONV_PREINT_INLINE d4 omega(const ImuSample& s, int k) const { return simd::Splat(s.gyro.data()[k]) - bg[k]; }
};

/// One manifold step (start-frame chart) as a functor over the state buffers.
template <bool kCovariance, class W>
struct ManifoldStepper {
  NoiseVariances q;
  Inputs u;
  B dR;
  d4 dp, dv;
  double dt_total;

  IMUCONV_PREINT_INLINE void operator()(const ImuSample& s, double dt, const State<W>& __restrict in,
                                        State<W>& __restrict out) {
    using namespace simd;
    const d4 vdt = Splat(dt);
    const d4 phi = vdt * u.omega(s);
    const double t2 = Dot(phi, phi);
    ExpJrCoefs k;
    if (t2 < so3::detail::kSeriesBelow * so3::detail::kSeriesBelow) {
      k = ExpJrSeries(t2);
    } else {
      const double t = std::sqrt(t2);
      double sh, ch;
      SinCosNonNegative(0.5 * t, sh, ch);
      k = ExpJrClosed(t, 1.0 / t2, sh, ch);
    }
    // dR Exp(phi) = dR + a T1 + b T2 and dR Jl(phi) = dR + b T1 + c T2 with
    // T1 = dR [phi]x, T2 = dR [phi]x^2: no 3x3 product.
    const d4 p0 = vdt * u.omega(s, 0), p1 = vdt * u.omega(s, 1), p2 = vdt * u.omega(s, 2);
    const B T1 = TimesSkew(dR, p0, p1, p2), T2 = TimesSkew(T1, p0, p1, p2);
    const d4 a_start = dR.c[0] * u.acc(s, 0) + dR.c[1] * u.acc(s, 1) + dR.c[2] * u.acc(s, 2);

    StepConsts<W> m;
    m.N = dR;
    m.C = AddScaled(AddScaled(dt * dR, dt * k.b, T1), dt * k.c, T2);  // dt dR Jl(phi)
    m.cc_u = dR.c[0] * p0 + dR.c[1] * p1 + dR.c[2] * p2;              // dR Jl Jl^T dR^T = I + g [dR phi]x^2
    m.b = vdt * a_start;
    FinishStepConsts<kCovariance>(m, dt, SymmetricSquareCoef(k.b, k.c, t2), q, in.s_ba, in.s_bg);
    PropagateBlocks<kCovariance>(StartFrameTransition<W>(m.b), m, in, out);

    dp += vdt * dv + Splat(0.5 * dt * dt) * a_start;
    dv += vdt * a_start;
    dR = AddScaled(AddScaled(dR, k.a, T1), k.b, T2);
    dt_total += dt;
  }
};

/// Manifold scheme over the window, start-frame chart; kMidpoint holds the mean of
/// adjacent knots instead of knot j (see HeldKnots::held).
template <bool kCovariance, class W, bool kMidpoint = false>
IMUCONV_PREINT_INLINE void ManifoldInterval(const PreintegrationInput& in, ManifoldIncrement& inc, Blocks& result) {
  using namespace simd;
  State<W> b0, b1;
  ZeroState(b0);
  ManifoldStepper<kCovariance, W> step{NoiseVariances(in.noise), Inputs(in), Identity(), Splat(0.0),
                                       Splat(0.0), 0.0};
  result = ToBlocks(RunHeldKnots<W, kMidpoint>(in, b0, b1, step));
  inc.dt = step.dt_total;
  ToEigen(step.dR, inc.dR);
  inc.dp = ToEigen(step.dp);
  inc.dv = ToEigen(step.dv);
}

/// The tangent step's vectors whose entries are broadcast, kept in memory.
struct TangentVectors {
  d4 theta, dw, ev;
};

/// One tangent step (additive chart of xi) as a functor over the state buffers.
template <bool kCovariance, class W>
struct TangentStepper {
  NoiseVariances q;
  Inputs u;
  d4 theta, p, v;
  double dt_total;

  IMUCONV_PREINT_INLINE void operator()(const ImuSample& s, double dt, const State<W>& __restrict in,
                                        State<W>& __restrict out) {
    using namespace simd;
    const d4 vdt = Splat(dt);
    const d4 omega = u.omega(s), acc = u.acc(s);
    const d4 th = theta;
    const double t2 = Dot(th, th);
    TangentCoefs c;
    if (t2 < kTangentSeriesBelow * kTangentSeriesBelow) {
      c.d = JrInvSeriesD(t2);  // the only coefficient theta' needs: keep it first
      const d4 abce = TangentSeriesABCE(t2);
      c.a = abce[0];
      c.b = abce[1];
      c.c = abce[2];
      c.e = abce[3];
    } else {
      c = TangentClosed(std::sqrt(t2), t2);
    }
    // theta' = theta + dt Jr^{-1}(theta) omega, with
    // Jr^{-1} omega = omega + 1/2 theta x omega + d theta x (theta x omega).
    const double tw = Dot(th, omega);
    const d4 txtxw = th * Splat(tw) - omega * Splat(t2);
    theta = th + vdt * (omega + Splat(0.5) * Cross(th, omega) + Splat(c.d) * txtxw);

    // R acc = acc + a theta x acc + b theta x (theta x acc).
    const d4 a_start = Splat(1.0 - c.b * t2) * acc + Splat(c.a) * Cross(th, acc) + Splat(c.b * Dot(th, acc)) * th;

    TangentVectors tv{th, Splat(dt * c.d) * omega, {}};
    tv.ev = Splat(dt * c.e) * txtxw - Splat(2.0) * tv.dw;
    InMemory(tv);
    // theta's [.]x and theta theta^T, by columns (entries broadcast from memory).
    const So3Basis basis{{{__builtin_shufflevector(th, -th, 3, 2, 5, 3), __builtin_shufflevector(th, -th, 6, 3, 0, 3),
                           __builtin_shufflevector(th, -th, 1, 4, 3, 3)}},
                         {{th * Splat(tv.theta[0]), th * Splat(tv.theta[1]), th * Splat(tv.theta[2])}}};
    StepConsts<W> m;
    m.N = Poly(basis, 1.0 - c.b * t2, c.a, c.b);                   // R
    m.C = Poly(basis, dt * (1.0 - c.d * t2), 0.5 * dt, dt * c.d);  // dt Jr^{-1}
    m.cc_u = th;                                                    // Jr^{-1} Jr^{-T} = I + g [theta]x^2
    FinishStepConsts<kCovariance>(m, dt, SymmetricSquareCoef(0.5, c.d, t2), q, in.s_ba, in.s_bg);
    GeneralTransition<W> tr;  // kept in memory: its entries are broadcast
    // K = -dt [R acc]x Jl(theta): the columns of Jl crossed with dt R acc.
    {
      const B Jl = Poly(basis, 1.0 - c.c * t2, c.b, c.c);
      const d4 bk = vdt * a_start, bk1 = Yzx(bk);
      for (int j = 0; j < 3; ++j) tr.K.c[j] = Yzx(Jl.c[j] * bk1 - Yzx(Jl.c[j]) * bk);
    }
    // A_tt = I + dt D, D = (d theta.omega) I - 1/2 [omega]x + theta (d omega)^T
    //                      + (e theta x (theta x omega) - 2 d omega) theta^T.
    {
      const d4 a0 = Splat(1.0 + dt * c.d * tw), hw = Splat(-0.5 * dt) * omega, mhw = -hw;
      const d4 w0 = __builtin_shufflevector(hw, mhw, 3, 2, 5, 3), w1 = __builtin_shufflevector(hw, mhw, 6, 3, 0, 3),
               w2 = __builtin_shufflevector(hw, mhw, 1, 4, 3, 3);
      tr.A.c[0] = a0 * kE0 + w0 + th * Splat(tv.dw[0]) + tv.ev * Splat(tv.theta[0]);
      tr.A.c[1] = a0 * kE1 + w1 + th * Splat(tv.dw[1]) + tv.ev * Splat(tv.theta[1]);
      tr.A.c[2] = a0 * kE2 + w2 + th * Splat(tv.dw[2]) + tv.ev * Splat(tv.theta[2]);
    }
    InMemory(tr.A);
    InMemory(tr.K);
    tr.AK = Pair<W>(tr.A, tr.K);
    tr.dA = Pair<W>(tr.A, tr.A);
    tr.dK = Pair<W>(tr.K, tr.K);
    PropagateBlocks<kCovariance>(tr, m, in, out);

    p += vdt * v + Splat(0.5 * dt * dt) * a_start;
    v += vdt * a_start;
    dt_total += dt;
  }
};

/// Tangent scheme over the window, additive chart of xi.
template <bool kCovariance, class W>
IMUCONV_PREINT_INLINE void TangentInterval(const PreintegrationInput& in, TangentIncrement& inc, Blocks& result) {
  using namespace simd;
  State<W> b0, b1;
  ZeroState(b0);
  TangentStepper<kCovariance, W> step{NoiseVariances(in.noise), Inputs(in), Splat(0.0), Splat(0.0),
                                      Splat(0.0), 0.0};
  result = ToBlocks(RunHeldKnots(in, b0, b1, step));
  inc.dt = step.dt_total;
  for (int k = 0; k < 3; ++k) {
    inc.xi(k) = step.theta[k];
    inc.xi(3 + k) = step.p[k];
    inc.xi(6 + k) = step.v[k];
  }
}

// ---------------------------------------------------------------------------------------
// The baseline x86-64 instance. Without AVX the 4-lane blocks above are emulated poorly, so
// CPUs without AVX2 and FMA run the same recursion on Eigen 3x3 blocks (manifold in the
// chart (dR Exp(dtheta), dp + ddp, dv + ddv), converted to NavState at the end).

namespace legacy {

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

  c.s_ba += dt * q.accel_walk;
  c.s_bg += dt * q.gyro_walk;
}


/// One manifold step with its Jacobians in the chart (dR Exp(dtheta), dp + ddp, dv + ddv):
///   A_tt = E^T,  K = -dR [acc]x dt,  N = dR,  C_t = Jr(omega dt) dt.
inline void ManifoldStepRightChart(const Vec3& acc, const Vec3& omega, double dt, ManifoldIncrement& s,
                                   StepJacobians& J) {
  const double h = 0.5 * dt * dt;
  const Vec3 phi = omega * dt;
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const ExpJrCoefs k = ComputeExpJrCoefs(t, t2);
  const Mat3 S = so3::skew(phi), S2 = S * S;
  const Mat3 E = Mat3::Identity() + k.a * S + k.b * S2;
  const Mat3 Jr = Mat3::Identity() - k.b * S + k.c * S2;
  J.dt = dt;
  J.A_tt = E.transpose();
  J.K.noalias() = (-dt) * s.dR * so3::skew(acc);
  J.N = s.dR;
  J.C_t = dt * Jr;
  const Vec3 a_start = s.dR * acc;
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


template <bool kCovariance, typename StepFn>
inline void Run(const PreintegrationInput& in, StepFn step, BiasJacobians& H, CombinedCovariance& cov) {
  const SampleWindow& w = in.window;
  const NoiseVariances q = NoiseVariances(in.noise);
  StepJacobians J;
  for (std::size_t j = 0; j + 1 < w.size(); ++j) {
    const ImuSample& s = w[j];
    step(Vec3(s.accel - in.ba), Vec3(s.gyro - in.bg), w[j + 1].t - s.t, J);
    PropagateBiasJacobians(J, H);
    if constexpr (kCovariance) PropagateCombined(J, q, cov);
  }
}

}  // namespace legacy

// ---------------------------------------------------------------------------------------
// Per-ISA instances and the dispatch.

enum class IsaLevel { kBaseline = 0, kAvx2 = 1, kAvx512 = 2 };

// W: the pair type of the instance (8-lane vectors only where AVX-512 makes them native).
#define IMUCONV_PREINT_INSTANCE(NAME, ATTR, W)                                                          \
  template <bool kCov, bool kMid>                                                                       \
  ATTR void ManifoldInterval##NAME(const PreintegrationInput& in, ManifoldIncrement& inc, Blocks& r) { \
    ManifoldInterval<kCov, W, kMid>(in, inc, r);                                                        \
  }                                                                                                     \
  template <bool kCov>                                                                                  \
  ATTR void TangentInterval##NAME(const PreintegrationInput& in, TangentIncrement& inc, Blocks& r) {   \
    TangentInterval<kCov, W>(in, inc, r);                                                               \
  }

IMUCONV_PREINT_INSTANCE(Baseline, , simd::d4x2)
#if IMUCONV_PREINT_X86_DISPATCH
IMUCONV_PREINT_INSTANCE(Avx2, __attribute__((target("avx2,fma"))), simd::d4x2)
IMUCONV_PREINT_INSTANCE(Avx512, __attribute__((target("avx512f,avx512vl,avx512dq,avx512bw,avx2,fma"))), simd::d8)
#endif
#undef IMUCONV_PREINT_INSTANCE

inline bool IsaLevelAvailable(IsaLevel level) {
#if IMUCONV_PREINT_X86_DISPATCH
  switch (level) {
    case IsaLevel::kBaseline: return true;
    case IsaLevel::kAvx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case IsaLevel::kAvx512:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("avx512f") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512bw");
  }
  return false;
#else
  return level == IsaLevel::kBaseline;
#endif
}

/// The widest level this CPU runs, decided once.
inline IsaLevel BestIsaLevel() {
  static const IsaLevel best = IsaLevelAvailable(IsaLevel::kAvx512) ? IsaLevel::kAvx512
                               : IsaLevelAvailable(IsaLevel::kAvx2) ? IsaLevel::kAvx2
                                                                    : IsaLevel::kBaseline;
  return best;
}

template <bool kCov, bool kMidpoint = false>
inline void RunManifold(IsaLevel level, const PreintegrationInput& in, ManifoldIncrement& inc, Blocks& r) {
#if IMUCONV_PREINT_X86_DISPATCH
  if (level == IsaLevel::kAvx512) return ManifoldIntervalAvx512<kCov, kMidpoint>(in, inc, r);
  if (level == IsaLevel::kAvx2) return ManifoldIntervalAvx2<kCov, kMidpoint>(in, inc, r);
#endif
  (void)level;
  ManifoldIntervalBaseline<kCov, kMidpoint>(in, inc, r);
}

template <bool kCov>
inline void RunTangent(IsaLevel level, const PreintegrationInput& in, TangentIncrement& inc, Blocks& r) {
#if IMUCONV_PREINT_X86_DISPATCH
  if (level == IsaLevel::kAvx512) return TangentIntervalAvx512<kCov>(in, inc, r);
  if (level == IsaLevel::kAvx2) return TangentIntervalAvx2<kCov>(in, inc, r);
#endif
  (void)level;
  TangentIntervalBaseline<kCov>(in, inc, r);
}

// ---------------------------------------------------------------------------------------
// Assembly of the outputs (once per interval).

/// The 15x15 covariance [P X; X^T S] in the kernel's chart, exactly symmetric.
inline Mat15 AssembleCovariance(const Blocks& c) {
  Mat15 S = Mat15::Zero();
  const auto put = [&S](int i, int j, const B& m) { simd::ToEigen(m, S.block<3, 3>(3 * i, 3 * j)); };
  put(0, 0, c.Ptt);
  put(1, 0, c.Ppt);
  put(2, 0, c.Pvt);
  put(1, 1, c.Ppp);
  put(2, 1, c.Pvp);
  put(2, 2, c.Pvv);
  put(1, 3, c.Xpa);
  put(2, 3, c.Xva);
  put(0, 4, c.Xtg);
  put(1, 4, c.Xpg);
  put(2, 4, c.Xvg);
  S.block<3, 3>(9, 9).diagonal().setConstant(c.s_ba);
  S.block<3, 3>(12, 12).diagonal().setConstant(c.s_bg);
  // P's lower blocks and X's blocks are each stored once: mirror them. P's diagonal
  // blocks are symmetric in exact arithmetic, not in rounding: average them.
  for (int j = 0; j < 15; ++j)
    for (int i = j + 1; i < 15; ++i) {
      if (i < 9 && i / 3 == j / 3) {
        S(i, j) = S(j, i) = 0.5 * (S(i, j) + S(j, i));
      } else if (j < 9) {
        S(i, j) = S(j, i) = S(i, j) + S(j, i);  // exactly one of the two was written
      }
    }
  return S;
}

/// 9x6 bias Jacobian, columns [ba, bg] (GTSAM's layout), in the kernel's chart.
inline Mat96 AssembleBiasJacobian(const Blocks& c) {
  Mat96 J = Mat96::Zero();
  simd::ToEigen(c.Hpa, J.block<3, 3>(3, 0));
  simd::ToEigen(c.Hva, J.block<3, 3>(6, 0));
  simd::ToEigen(c.Htg, J.block<3, 3>(0, 3));
  simd::ToEigen(c.Hpg, J.block<3, 3>(3, 3));
  simd::ToEigen(c.Hvg, J.block<3, 3>(6, 3));
  return J;
}

}  // namespace detail

/// Which compiled instance of the interval kernels to run: kAuto picks the widest one the
/// CPU supports (decided once); the others exist so tests can run every instance.
enum class Isa { kAuto, kBaseline, kAvx2, kAvx512 };

/// Whether `isa` can run on this CPU (kAuto always can).
inline bool IsaAvailable(Isa isa) {
  switch (isa) {
    case Isa::kAuto: return true;
    case Isa::kBaseline: return true;
    case Isa::kAvx2: return detail::IsaLevelAvailable(detail::IsaLevel::kAvx2);
    case Isa::kAvx512: return detail::IsaLevelAvailable(detail::IsaLevel::kAvx512);
  }
  return false;
}

namespace detail {
inline IsaLevel ResolveIsa(Isa isa) {
  switch (isa) {
    case Isa::kBaseline: return IsaLevel::kBaseline;
    case Isa::kAvx2: return IsaLevel::kAvx2;
    case Isa::kAvx512: return IsaLevel::kAvx512;
    case Isa::kAuto: break;
  }
  return BestIsaLevel();
}
}  // namespace detail

// ---------------------------------------------------------------------------------------
// Interval drivers.

namespace detail {
/// 0 for finite data; NaN if any entry is NaN or infinite (0 * inf = NaN).
inline double NonFiniteProbe(const ImuSample& s) {
  return 0.0 * s.t + 0.0 * s.gyro.x() + 0.0 * s.gyro.y() + 0.0 * s.gyro.z() + 0.0 * s.accel.x() + 0.0 * s.accel.y() +
         0.0 * s.accel.z();
}
}  // namespace detail

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
  // One pass without branches over the knots; the error, if any, is located afterwards.
  double probe = detail::NonFiniteProbe(w.first) + detail::NonFiniteProbe(w.last);
  bool increasing = true;
  double t_prev = w.first.t;
  for (std::size_t i = w.begin; i < w.end; ++i) {
    const ImuSample& s = w.samples[i];
    probe += detail::NonFiniteProbe(s);
    increasing &= s.t > t_prev;
    t_prev = s.t;
  }
  increasing &= w.last.t > t_prev;
  if (probe == 0.0 && increasing) return Status::Ok();
  const std::size_t count = w.size();
  for (std::size_t j = 0; j < count; ++j) {
    const ImuSample& s = w[j];
    if (!std::isfinite(s.t) || !s.gyro.allFinite() || !s.accel.allFinite())
      return Status::Error("knot " + std::to_string(j) + " of the window is not finite");
    if (j > 0 && !(s.t > w[j - 1].t))
      return Status::Error("knot times must increase strictly (knot " + std::to_string(j) + ")");
  }
  return Status::Error("window data are not finite");  // not reached: the scan above finds it
}

inline void FillCommon(const PreintegrationInput& in, double dt, NativePreintegration& out) {
  out.dt = dt;
  out.delta.dbg.setZero();
  out.delta.dba.setZero();
  out.bg_hat = in.bg;
  out.ba_hat = in.ba;
}

/// Manifold scheme over the window; covariance in the NavState chart ("gtsam_manifold"),
/// bias Jacobian in dR Exp(dtheta), additive dp, dv ("gtsam_manifold_jacobian").
/// Without kCovariance, out.cov is zero (for re-integrations that need the mean only).
template <bool kCovariance = true>
inline Status IntegrateManifold(const PreintegrationInput& in, NativePreintegration& out,
                                ManifoldIncrement* increment = nullptr, Isa isa = Isa::kAuto) {
  Status st = CheckPreintegrationInput(in);
  if (!st.ok()) return st;
  ManifoldIncrement inc;
  if (detail::ResolveIsa(isa) == detail::IsaLevel::kBaseline) {
    detail::legacy::BiasJacobians H;
    detail::legacy::CombinedCovariance cov;
    detail::legacy::Run<kCovariance>(
        in, [&inc](const Vec3& a, const Vec3& w, double dt, StepJacobians& J) { detail::legacy::ManifoldStepRightChart(a, w, dt, inc, J); },
        H, cov);
    FillCommon(in, inc.dt, out);
    out.delta.dR = inc.dR;
    out.delta.dp = inc.dp;
    out.delta.dv = inc.dv;
    out.J_bias = H.Assemble();
    if constexpr (kCovariance) out.cov = detail::legacy::ManifoldCovarianceInNavStateChart(inc.dR, cov);
    else out.cov.setZero();
    if (increment) *increment = inc;
    return Status::Ok();
  }
  detail::Blocks r;
  detail::RunManifold<kCovariance>(detail::ResolveIsa(isa), in, inc, r);
  FillCommon(in, inc.dt, out);
  out.delta.dR = inc.dR;
  out.delta.dp = inc.dp;
  out.delta.dv = inc.dv;
  // Start-frame chart -> NavState chart / right rotation perturbation: phi = dR dtheta and
  // dp_start = dR dp_nav, i.e. T = blockdiag(dR^T, dR^T, dR^T) on the 9 increment rows.
  const Mat3 Rt = inc.dR.transpose();
  out.J_bias = detail::AssembleBiasJacobian(r);
  out.J_bias.topRows<3>() = Rt * out.J_bias.topRows<3>();
  if constexpr (kCovariance) {
    Mat15 S = detail::AssembleCovariance(r);
    for (int b = 0; b < 9; b += 3) S.middleRows<3>(b) = Rt * S.middleRows<3>(b);
    for (int b = 0; b < 9; b += 3) S.middleCols<3>(b) = S.middleCols<3>(b) * inc.dR;
    out.cov = 0.5 * (S + S.transpose());  // rows and columns were rotated in separate roundings
  } else {
    out.cov.setZero();
  }
  if (increment) *increment = inc;
  return Status::Ok();
}

/// Tangent scheme over the window; covariance and bias Jacobian additive on the tangent
/// 9-vector ("gtsam_tangent"). Without kCovariance, out.cov is zero.
template <bool kCovariance = true>
inline Status IntegrateTangent(const PreintegrationInput& in, NativePreintegration& out,
                               TangentIncrement* increment = nullptr, Isa isa = Isa::kAuto) {
  Status st = CheckPreintegrationInput(in);
  if (!st.ok()) return st;
  TangentIncrement inc;
  if (detail::ResolveIsa(isa) == detail::IsaLevel::kBaseline) {
    detail::legacy::BiasJacobians H;
    detail::legacy::CombinedCovariance cov;
    detail::legacy::Run<kCovariance>(
        in, [&inc](const Vec3& a, const Vec3& w, double dt, StepJacobians& J) { TangentStep(a, w, dt, inc, J); }, H, cov);
    FillCommon(in, inc.dt, out);
    out.delta.dR = so3::Exp(inc.xi.segment<3>(0));
    out.delta.dp = inc.xi.segment<3>(3);
    out.delta.dv = inc.xi.segment<3>(6);
    out.J_bias = H.Assemble();
    if constexpr (kCovariance) out.cov = cov.Assemble();
    else out.cov.setZero();
    if (increment) *increment = inc;
    return Status::Ok();
  }
  detail::Blocks r;
  detail::RunTangent<kCovariance>(detail::ResolveIsa(isa), in, inc, r);
  FillCommon(in, inc.dt, out);
  out.delta.dR = so3::Exp(inc.xi.segment<3>(0));
  out.delta.dp = inc.xi.segment<3>(3);
  out.delta.dv = inc.xi.segment<3>(6);
  out.J_bias = detail::AssembleBiasJacobian(r);
  if constexpr (kCovariance) out.cov = detail::AssembleCovariance(r);
  else out.cov.setZero();
  if (increment) *increment = inc;
  return Status::Ok();
}

}  // namespace imuconv::kernels

#pragma GCC diagnostic pop
// GCC reports -Wpsabi for the always-inline 4-lane helpers at the end of the translation
// unit, where the push/pop above no longer applies; none of them is ever emitted out of
// line, so there is no ABI to change.
#pragma GCC diagnostic ignored "-Wpsabi"
#undef IMUCONV_PREINT_INLINE
#undef IMUCONV_PREINT_X86_DISPATCH
