// PreintegrationFactor: the measurement is the bridge's (Preintegrate, in the reference charts,
// from any propagator or preintegrator) and the residual is the bridge's (ComputeResidual in the
// reference state chart `left`); this file adds only the fixed whitening and re-integration.
#include "imuconv/ceres/preintegration_factor.h"

#include "sqrt_information.h"

#include <cmath>
#include <sstream>
#include <utility>

#include "imuconv/prediction.h"
#include "imuconv/window.h"

namespace imuconv::ceres_factors {

namespace {

bool Finite(const ImuSample& s) {
  return std::isfinite(s.t) && s.gyro.allFinite() && s.accel.allFinite();
}

// The samples must be finite and strictly increasing in time (MakeWindow's precondition, which it
// does not check itself), and [t_s, t_e] a finite, non-empty interval they cover.
void CheckSamples(const std::vector<ImuSample>& samples, double t_s, double t_e) {
  if (!std::isfinite(t_s) || !std::isfinite(t_e) || !(t_s < t_e)) {
    std::ostringstream os;
    os.precision(17);
    os << "preintegration factor: the interval [" << t_s << ", " << t_e
       << "] s is not a finite interval with t_s < t_e";
    throw Error(os.str());
  }
  for (std::size_t k = 0; k < samples.size(); ++k) {
    if (!Finite(samples[k]))
      throw Error("preintegration factor: IMU sample " + std::to_string(k) +
                  " has a non-finite time, angular rate or specific force");
    if (k > 0 && !(samples[k].t > samples[k - 1].t))
      throw Error("preintegration factor: IMU sample " + std::to_string(k) +
                  " is not later than the sample before it (times must increase strictly)");
  }
}

void CheckNoise(const ImuNoise& n) {
  for (double d :
       {n.gyro_noise_density, n.accel_noise_density, n.gyro_random_walk, n.accel_random_walk})
    if (!std::isfinite(d) || d < 0.0)
      throw Error("preintegration factor: a noise density is negative or not finite");
}

}  // namespace

PreintegrationFactor::PreintegrationFactor(const Registry& reg, const PreintegrationMethod& method,
                                           std::vector<ImuSample> samples, double t_s, double t_e,
                                           const ImuNoise& noise, const Vec3& bg_hat,
                                           const Vec3& ba_hat,
                                           const PreintegrationFactorOptions& options)
    : reg_(&reg),
      method_(method),
      samples_(std::move(samples)),
      t_s_(t_s),
      t_e_(t_e),
      noise_(noise),
      options_(options) {
  if (!method_.propagator && !method_.preintegrator)
    throw Error("preintegration factor: the method '" + method_.id +
                "' is not resolved (ResolvePreintegrationMethod gives one)");
  CheckSamples(samples_, t_s_, t_e_);
  CheckNoise(noise_);
  if (!options_.gravity.allFinite()) throw Error("preintegration factor: gravity is not finite");
  if (std::isnan(options_.reintegrate_gyro_bias) || std::isnan(options_.reintegrate_accel_bias) ||
      options_.reintegrate_gyro_bias < 0.0 || options_.reintegrate_accel_bias < 0.0)
    throw Error("preintegration factor: a re-integration threshold is negative or NaN");
  Reintegrate(bg_hat, ba_hat);
}

void PreintegrationFactor::Reintegrate(const Vec3& bg, const Vec3& ba) {
  if (!bg.allFinite() || !ba.allFinite())
    throw Error("preintegration factor: the bias to integrate at is not finite");
  SampleWindow window;
  const Status made = MakeWindow(samples_.data(), samples_.size(), t_s_, t_e_, window);
  if (!made) throw Error("preintegration factor: " + made.message());
  Preintegrated m = Preintegrate(*reg_, method_, window, bg, ba, noise_);

  // The whitening is fixed per measurement: cov(r) at the measurement's own prediction (the end
  // state f(x_s, Delta x_se) of a start state at the identity with the integration bias, where
  // the bias correction vanishes), eq. residual-cov. For the Gtsam and Forster kinds it does not
  // depend on the start state, so it is the covariance at any pair of states the residual is
  // small at, and the cost below is a fixed least-squares function of the states.
  ImuState x_s;
  x_s.bg = bg;
  x_s.ba = ba;
  const ImuState x_e = Predict(x_s, m.delta, m.dt, options_.gravity);
  const Residual at_prediction =
      ComputeResidual(*reg_, options_.kind, m, x_s, x_e, "left", options_.gravity);
  Mat15 S;
  const detail::SqrtInformationStatus status = detail::InverseCholeskyFactor(at_prediction.cov, S);
  if (status == detail::SqrtInformationStatus::kNotPositiveDefinite)
    throw Error("preintegration factor: the residual covariance over [" + std::to_string(t_s_) +
                ", " + std::to_string(t_e_) +
                "] s is not positive definite (are all four noise densities positive?)");
  if (status == detail::SqrtInformationStatus::kNearSingular)
    throw Error("preintegration factor: the residual covariance is too close to singular");
  measurement_ = std::move(m);
  sqrt_information_ = S;
}

bool PreintegrationFactor::ReintegrateIfMoved(const Vec3& bg, const Vec3& ba) {
  // Strictly beyond the threshold, so that +infinity never re-integrates and 0 re-integrates at
  // any change.
  const bool moved = (bg - measurement_.bg_hat).norm() > options_.reintegrate_gyro_bias ||
                     (ba - measurement_.ba_hat).norm() > options_.reintegrate_accel_bias;
  if (moved) Reintegrate(bg, ba);
  return moved;
}

Residual PreintegrationFactor::Evaluate(const ImuState& x_s, const ImuState& x_e) const {
  Residual r =
      ComputeResidual(*reg_, options_.kind, measurement_, x_s, x_e, "left", options_.gravity);
  const Mat15& S = sqrt_information_;
  r.r = S * r.r;
  r.H_start = S * r.H_start;
  r.H_end = S * r.H_end;
  r.H_increment = S * r.H_increment;
  r.cov = S * r.cov * S.transpose();
  return r;
}

}  // namespace imuconv::ceres_factors
