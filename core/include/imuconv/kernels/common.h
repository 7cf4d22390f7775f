// What the integrator kernels share besides the transition structure: the output modes,
// the squared noise densities, the input checks and a fused SO(3) exponential.
#pragma once

#include <cmath>
#include <sstream>

#include "imuconv/kernels/left_transition.h"
#include "imuconv/propagator.h"
#include "imuconv/so3.h"
#include "imuconv/status.h"
#include "imuconv/types.h"
#include "imuconv/window.h"

namespace imuconv::kernels {

/// Which outputs a kernel computes. The state-only mode is what finite-difference and
/// Monte Carlo tests re-run many times; the plugins use All.
enum class Outputs { State, StateAndTransition, All };

constexpr bool WantsTransition(Outputs o) { return o != Outputs::State; }
constexpr bool WantsCovariance(Outputs o) { return o == Outputs::All; }

/// The noise densities squared once per interval: the diagonal of the paper's Q (continuous).
struct NoiseVariances {
  double gyro, accel, gyro_walk, accel_walk;
  explicit NoiseVariances(const ImuNoise& n)
      : gyro(n.gyro_noise_density * n.gyro_noise_density),
        accel(n.accel_noise_density * n.accel_noise_density),
        gyro_walk(n.gyro_random_walk * n.gyro_random_walk),
        accel_walk(n.accel_random_walk * n.accel_random_walk) {}
};

namespace detail {
inline bool SampleFinite(const ImuSample& s) {
  return std::isfinite(s.t) && s.gyro.allFinite() && s.accel.allFinite();
}
}  // namespace detail

/// The checks every propagator makes before integrating: at least two knots with strictly
/// increasing times, and finite state, covariance, noise, gravity and samples. One pass over
/// the window; it only allocates when it reports an error.
inline Status CheckPropagationInput(const PropagationInput& in) {
  const SampleWindow& w = in.window;
  if (w.end < w.begin)
    return Status::Error("sample window is malformed (end before begin): fewer than two knots");
  if (w.end > w.begin && w.samples == nullptr)
    return Status::Error("sample window has interior knots but no samples");
  const auto& x = in.x_s;
  if (!(x.R.allFinite() && x.p.allFinite() && x.v.allFinite() && x.bg.allFinite() &&
        x.ba.allFinite()))
    return Status::Error("start state is not finite");
  if (!in.cov_s.allFinite()) return Status::Error("start covariance is not finite");
  if (!in.gravity.allFinite()) return Status::Error("gravity is not finite");
  const ImuNoise& n = in.noise;
  for (double d :
       {n.gyro_noise_density, n.accel_noise_density, n.gyro_random_walk, n.accel_random_walk})
    if (!(std::isfinite(d) && d >= 0.0))
      return Status::Error("noise densities must be finite and non-negative");
  const std::size_t knots = w.size();
  for (std::size_t j = 0; j < knots; ++j) {
    const ImuSample& s = w[j];
    if (!detail::SampleFinite(s)) {
      std::ostringstream msg;
      msg.precision(17);
      msg << "IMU knot " << j << " of " << knots << " (t = " << s.t << ") is not finite";
      return Status::Error(msg.str());
    }
    if (j > 0 && !(s.t > w[j - 1].t)) {
      std::ostringstream msg;
      msg.precision(17);
      msg << "IMU knot times must increase strictly: knot " << j << " at t = " << s.t
          << " follows t = " << w[j - 1].t;
      return Status::Error(msg.str());
    }
  }
  return Status::Ok();
}

/// Exp(phi) and, when Jr is not null, Jr(phi), sharing the angle and the [phi]x^2 term
/// (the closed forms and series of so3.h; [phi]x^2 = phi phi^T - |phi|^2 I needs no product).
inline void ExpAndJr(const Vec3& phi, Mat3& Exp, Mat3* Jr) {
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const Mat3 S = so3::skew(phi);
  Mat3 S2 = phi * phi.transpose();
  S2.diagonal().array() -= t2;
  const double b = so3::detail::coefB(t, t2);
  Exp = Mat3::Identity() + so3::detail::coefA(t, t2) * S + b * S2;
  if (Jr) *Jr = Mat3::Identity() - b * S + so3::detail::coefC(t, t2) * S2;
}

/// Jr^{-1}(phi) w, the body rate mapped to the rate of the exponential coordinates phi of
/// R(t) = R_0 Exp(phi(t)) (d/dt R = R [w]x); as a matrix-free form of so3::JrInv.
inline Vec3 JrInvTimes(const Vec3& phi, const Vec3& w) {
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const Vec3 phi_x_w = phi.cross(w);
  return w + 0.5 * phi_x_w + so3::detail::coefD(t, t2) * phi.cross(phi_x_w);
}

/// out = A B (or out += A B) for a tall A with three columns and a 3x3 B, written as axpys of
/// whole columns: for 15-row A these vectorise over the contiguous columns, where Eigen's
/// generic small-product path does not. `out` may be a block expression (hence Out&&).
template <typename A, typename Out>
inline void AssignTimes3x3(const Eigen::MatrixBase<A>& a, const Mat3& b, Out&& out) {
  for (int j = 0; j < 3; ++j)
    out.col(j) = a.col(0) * b(0, j) + a.col(1) * b(1, j) + a.col(2) * b(2, j);
}
template <typename A, typename Out>
inline void AddTimes3x3(const Eigen::MatrixBase<A>& a, const Mat3& b, Out&& out) {
  for (int j = 0; j < 3; ++j)
    out.col(j) += a.col(0) * b(0, j) + a.col(1) * b(1, j) + a.col(2) * b(2, j);
}

}  // namespace imuconv::kernels
