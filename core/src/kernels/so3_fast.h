// SO(3) coefficients for the preintegration kernel, each set from one sin/cos evaluation
// or one power series: Exp, Jr, Jl and Jr^{-1} as alpha I + beta [phi]x + gamma [phi]x^2
// (the closed forms and series of so3.h, fused), and a local sin/cos without a libm call.
// Shared by the step specification (steps.cpp), the portable path and every SIMD instance.
#pragma once

#include <cmath>
#include <cstdint>

#include "imuconv/so3.h"
#include "imuconv/types.h"
#include "kernel_config.h"

#if IMUCONV_KERNEL_HAS_VECTORS
#include "simd_block3.h"
#endif

IMUCONV_KERNEL_BEGIN

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
  constexpr double f2 = 0.5, f4 = f2 / 12.0, f6 = f4 / 30.0, f8 = f6 / 56.0, f10 = f8 / 90.0,
                   f12 = f10 / 132.0, f14 = f12 / 182.0, f16 = f14 / 240.0;
  const double ps =
      r +
      r * r2 *
          (-f3 +
           r2 * (f5 + r2 * (-f7 + r2 * (f9 + r2 * (-f11 + r2 * (f13 + r2 * (-f15 + r2 * f17)))))));
  const double pc =
      1.0 +
      r2 * (-f2 +
            r2 * (f4 + r2 * (-f6 + r2 * (f8 + r2 * (-f10 + r2 * (f12 + r2 * (-f14 + r2 * f16)))))));
  switch (n & 3) {
    case 0:
      s = ps, c = pc;
      break;
    case 1:
      s = pc, c = -ps;
      break;
    case 2:
      s = -ps, c = -pc;
      break;
    default:
      s = -pc, c = ps;
      break;
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
IMUCONV_KERNEL_INLINE double JrInvSeriesD(double x) {
  constexpr double c[18] = {0.08333333333333333,    0.001388888888888889,   3.306878306878307e-05,
                            8.267195767195768e-07,  2.08767569878681e-08,   5.284190138687493e-10,
                            1.3382536530684679e-11, 3.3896802963225827e-13, 8.586062056277845e-15,
                            2.174868698558062e-16,  5.5090028283602295e-18, 1.3954464685812522e-19,
                            3.534707039629467e-21,  8.953517427037546e-23,  2.267952452337683e-24,
                            5.744790668872202e-26,  1.455172475614865e-27,  3.6859949406653103e-29};
  const double x2 = x * x, x4 = x2 * x2, x8 = x4 * x4, x16 = x8 * x8;
  const double q0 = c[0] + c[1] * x, q1 = c[2] + c[3] * x, q2 = c[4] + c[5] * x,
               q3 = c[6] + c[7] * x;
  const double q4 = c[8] + c[9] * x, q5 = c[10] + c[11] * x, q6 = c[12] + c[13] * x,
               q7 = c[14] + c[15] * x;
  const double q8 = c[16] + c[17] * x;
  const double r0 = q0 + q1 * x2, r1 = q2 + q3 * x2, r2 = q4 + q5 * x2, r3 = q6 + q7 * x2;
  return ((r0 + r1 * x4) + (r2 + r3 * x4) * x8) + q8 * x16;
}

#if IMUCONV_KERNEL_HAS_VECTORS
using Lanes4 = simd::d4;
#else
/// Four lanes evaluated one by one where there are no vector extensions.
struct Lanes4 {
  double l[4];
  double operator[](int k) const { return l[k]; }
  friend Lanes4 operator+(const Lanes4& a, const Lanes4& b) {
    return {{a.l[0] + b.l[0], a.l[1] + b.l[1], a.l[2] + b.l[2], a.l[3] + b.l[3]}};
  }
  friend Lanes4 operator*(const Lanes4& a, const Lanes4& b) {
    return {{a.l[0] * b.l[0], a.l[1] * b.l[1], a.l[2] * b.l[2], a.l[3] * b.l[3]}};
  }
};
#endif

/// (sin t/t, (1 - cos t)/t^2, (t - sin t)/t^3, e(t)) from x = t^2 < 4, as one 4-lane
/// polynomial.
IMUCONV_KERNEL_INLINE Lanes4 TangentSeriesABCE(double x) {
  static constexpr Lanes4 c[20] = {
      {1.0, 0.5, 0.16666666666666666, 0.002777777777777778},
      {-0.16666666666666666, -0.041666666666666664, -0.008333333333333333, 0.00013227513227513228},
      {0.008333333333333333, 0.001388888888888889, 0.0001984126984126984, 4.96031746031746e-06},
      {-0.0001984126984126984, -2.48015873015873e-05, -2.7557319223985893e-06,
       1.670140559029448e-07},
      {2.7557319223985893e-06, 2.755731922398589e-07, 2.505210838544172e-08,
       5.2841901386874934e-09},
      {-2.505210838544172e-08, -2.08767569878681e-09, -1.6059043836821613e-10,
       1.6059043836821613e-10},
      {1.6059043836821613e-10, 1.1470745597729725e-11, 7.647163731819816e-13,
       4.745552414851616e-12},
      {-7.647163731819816e-13, -4.779477332387385e-14, -2.8114572543455206e-15,
       1.3737699290044552e-13},
      {2.8114572543455206e-15, 1.5619206968586225e-16, 8.22063524662433e-18, 3.914763657404511e-15},
      {-8.22063524662433e-18, -4.110317623312165e-19, -1.9572941063391263e-20,
       1.1018005656720459e-16},
      {1.9572941063391263e-20, 8.896791392450574e-22, 3.868170170630684e-23, 3.069982230878755e-18},
      {-3.868170170630684e-23, -1.6117375710961184e-24, -6.446950284384474e-26,
       8.483296895110721e-20},
      {6.446950284384474e-26, 2.4795962632247976e-27, 9.183689863795546e-29, 2.327914531029762e-21},
      {-9.183689863795546e-29, -3.279889237069838e-30, -1.1309962886447716e-31,
       6.350266866545513e-23},
      {1.1309962886447716e-31, 3.7699876288159054e-33, 1.216125041553518e-34,
       1.7234372006616606e-24},
      {-1.216125041553518e-34, -3.8003907548547434e-36, -1.151633562077195e-37,
       4.656551921967568e-26},
      {1.151633562077195e-37, 3.387157535521162e-39, 9.67759295863189e-41, 1.2532382798262054e-27},
      {-9.67759295863189e-41, -2.6882202662866363e-42, -7.265460179153071e-44,
       3.3612243325542163e-29},
      {7.265460179153071e-44, 1.911963205040282e-45, 4.902469756513544e-47, 8.987085179662393e-31},
      {-4.902469756513544e-47, -1.2256174391283858e-48, -2.9893108271424046e-50,
       2.3962687049928537e-32},
  };
  // Estrin's scheme (six FMA levels deep rather than Horner's nineteen: this sits on the
  // step's critical path, theta -> coefficients -> maps -> products).
#if IMUCONV_KERNEL_NARROW
  const Lanes4 v = simd::Splat(x);  // d4 is a struct of two 2-lane halves there
#elif IMUCONV_KERNEL_HAS_VECTORS
  const Lanes4 x0 = {x, 0.0, 0.0, 0.0}, v = __builtin_shufflevector(x0, x0, 0, 0, 0, 0);
#else
  const Lanes4 v = {{x, x, x, x}};
#endif
  const Lanes4 v2 = v * v, v4 = v2 * v2, v8 = v4 * v4, v16 = v8 * v8;
  Lanes4 q[10];
  for (int k = 0; k < 10; ++k) q[k] = c[2 * k] + c[2 * k + 1] * v;
  const Lanes4 r0 = q[0] + q[1] * v2, r1 = q[2] + q[3] * v2, r2 = q[4] + q[5] * v2,
               r3 = q[6] + q[7] * v2, r4 = q[8] + q[9] * v2;
  return ((r0 + r1 * v4) + (r2 + r3 * v4) * v8) + r4 * v16;
}

/// Coefficients of Exp = I + a S + b S^2, Jr = I - b S + c S^2 (S = [phi]x, t = |phi|).
struct ExpJrCoefs {
  double a, b, c;
};

/// Below so3::detail::kSeriesBelow: the series of so3.h (in t^2 only, truncation < 1e-17),
/// with the divisions by constants as multiplications.
IMUCONV_KERNEL_INLINE ExpJrCoefs ExpJrSeries(double t2) {
  constexpr double r6 = 1.0 / 6.0, r20 = 1.0 / 20.0, r42 = 1.0 / 42.0, r72 = 1.0 / 72.0,
                   r12 = 1.0 / 12.0, r30 = 1.0 / 30.0, r56 = 1.0 / 56.0, r90 = 1.0 / 90.0,
                   r110 = 1.0 / 110.0;
  return {1.0 - t2 * r6 * (1.0 - t2 * r20 * (1.0 - t2 * r42 * (1.0 - t2 * r72))),
          0.5 * (1.0 - t2 * r12 * (1.0 - t2 * r30 * (1.0 - t2 * r56 * (1.0 - t2 * r90)))),
          r6 * (1.0 - t2 * r20 * (1.0 - t2 * r42 * (1.0 - t2 * r72 * (1.0 - t2 * r110))))};
}

/// Closed forms from sin/cos of the half angle: sin t = 2 sh ch, 1 - cos t = 2 sh^2.
IMUCONV_KERNEL_INLINE ExpJrCoefs ExpJrClosed(double t, double inv_t2, double sh, double ch) {
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

IMUCONV_KERNEL_INLINE TangentCoefs ComputeTangentCoefs(double t, double t2) {
  if (!(t < kTangentSeriesBelow)) return TangentClosed(t, t2);
  const Lanes4 abce = TangentSeriesABCE(t2);
  return {abce[0], abce[1], abce[2], JrInvSeriesD(t2), abce[3]};
}

/// C C^T for C = dt (I + beta S + delta S^2) with S skew (Jl, Jr, Jr^{-1} and their
/// rotations): (I + beta S + delta S^2)(I - beta S + delta S^2) = I + g S^2 with
/// g = 2 delta - beta^2 - delta^2 t^2 (S^3 = -t^2 S), so C C^T = dt^2 (I + g [u]x^2).
IMUCONV_KERNEL_INLINE double SymmetricSquareCoef(double beta, double delta, double t2) {
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

IMUCONV_KERNEL_END
