// SO(3) exponential and logarithm with their right and left Jacobians.
//
// Convention, stated once: Exp(phi) = exp([phi]x); the right Jacobian Jr satisfies
// Exp(phi + d) ~= Exp(phi) Exp(Jr(phi) d), the left Jacobian Jl(phi) = Jr(-phi) satisfies
// Exp(phi + d) ~= Exp(Jl(phi) d) Exp(phi). Every coefficient below is evaluated in a form
// without cancellation, with Taylor series below |phi| = 0.1 (truncation < 1e-17), and
// Log goes through a quaternion so it stays accurate up to |phi| = pi.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace imuconv::so3 {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

inline Mat3 skew(const Vec3& w) {
  Mat3 S;
  S << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return S;
}

namespace detail {
constexpr double kSeriesBelow = 0.1;  // |phi| below which Taylor series are used

// a = sin(t)/t
inline double coefA(double t, double t2) {
  if (t < kSeriesBelow)
    return 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0)));
  return std::sin(t) / t;
}
// b = (1 - cos t)/t^2 = 2 sin^2(t/2)/t^2
inline double coefB(double t, double t2) {
  if (t < kSeriesBelow)
    return 0.5 * (1.0 - t2 / 12.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0 * (1.0 - t2 / 90.0))));
  const double s = std::sin(0.5 * t);
  return 2.0 * s * s / t2;
}
// c = (t - sin t)/t^3
inline double coefC(double t, double t2) {
  if (t < kSeriesBelow)
    return (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0 * (1.0 - t2 / 72.0 * (1.0 - t2 / 110.0)))) / 6.0;
  return (t - std::sin(t)) / (t2 * t);
}
// d = 1/t^2 - cot(t/2)/(2t), the [phi]x^2 coefficient of Jr^{-1}; finite at t = pi.
inline double coefD(double t, double t2) {
  if (t < kSeriesBelow)
    return 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0 + t2 * t2 * t2 / 1209600.0;
  return 1.0 / t2 - 0.5 / (t * std::tan(0.5 * t));
}
}  // namespace detail

/// Exp(phi) = I + a [phi]x + b [phi]x^2.
inline Mat3 Exp(const Vec3& phi) {
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const Mat3 S = skew(phi);
  return Mat3::Identity() + detail::coefA(t, t2) * S + detail::coefB(t, t2) * (S * S);
}

/// Log(R) for a rotation matrix, through a unit quaternion with w >= 0 (robust near pi).
inline Vec3 Log(const Mat3& R) {
  Eigen::Quaterniond q(R);
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const Vec3 u = q.vec();
  const double n = u.norm(), w = q.w();
  // phi = 2 atan2(n, w) u / n; series of atan for small n/w.
  if (n < 1e-6 * w) {
    const double r2 = (n / w) * (n / w);
    return (2.0 / w) * (1.0 - r2 / 3.0 + r2 * r2 / 5.0) * u;
  }
  return (2.0 * std::atan2(n, w) / n) * u;
}

/// Right Jacobian Jr(phi) = I - b [phi]x + c [phi]x^2.
inline Mat3 Jr(const Vec3& phi) {
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const Mat3 S = skew(phi);
  return Mat3::Identity() - detail::coefB(t, t2) * S + detail::coefC(t, t2) * (S * S);
}

/// Left Jacobian Jl(phi) = Jr(-phi) = I + b [phi]x + c [phi]x^2.
inline Mat3 Jl(const Vec3& phi) {
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const Mat3 S = skew(phi);
  return Mat3::Identity() + detail::coefB(t, t2) * S + detail::coefC(t, t2) * (S * S);
}

/// Jr^{-1}(phi) = I + 1/2 [phi]x + d [phi]x^2.
inline Mat3 JrInv(const Vec3& phi) {
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const Mat3 S = skew(phi);
  return Mat3::Identity() + 0.5 * S + detail::coefD(t, t2) * (S * S);
}

/// Jl^{-1}(phi) = I - 1/2 [phi]x + d [phi]x^2.
inline Mat3 JlInv(const Vec3& phi) {
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const Mat3 S = skew(phi);
  return Mat3::Identity() - 0.5 * S + detail::coefD(t, t2) * (S * S);
}

/// Rotation matrix from a Hamilton quaternion given as w, x, y, z (normalised first).
inline Mat3 FromQuaternionWxyz(double w, double x, double y, double z) {
  Eigen::Quaterniond q(w, x, y, z);
  q.normalize();
  return q.toRotationMatrix();
}

/// Hamilton quaternion [w, x, y, z] of R, with w >= 0.
inline Eigen::Vector4d ToQuaternionWxyz(const Mat3& R) {
  Eigen::Quaterniond q(R);
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  return Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
}

}  // namespace imuconv::so3
