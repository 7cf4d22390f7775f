// VINS-Fusion's preintegration (HKUST-Aerial-Robotics/VINS-Fusion, IntegrationBase,
// midpoint scheme), reproduced to round-off: the increment, the 15x15 Jacobian product and
// the 15x15 covariance in its own error state and noise interpretation.
//
// The step over knots k, k+1 of the window (dt = t_k+1 - t_k, bias estimate removed):
//   w   = (w_k + w_k+1)/2 - bg
//   q'  = q (x) [1, w dt/2]                      -- not normalized within the step
//   a   = (q (a_k - ba) + q' (a_k+1 - ba)) / 2   -- q' applied as Eigen applies any quaternion
//   p'  = p + v dt + a dt^2/2,  v' = v + a dt,   then q = normalize(q')
// The rotation matrices of the first-order step matrix F (15x15) and the noise map V
// (15x18) are Eigen's unit-quaternion formula applied to the unnormalized q', as upstream
// does; for |w| dt = 0.03 that changes them by about 2e-4 relative, far above round-off.
//
// Error state `vins_fusion`, order [p, theta, v, ba, bg]: dp additive, q = q^ (x) [1, dtheta/2]
// (right, start frame: to first order Delta R = Delta R^ Exp(dtheta)), dv additive, the bias
// blocks additive (b = b^ + db). The Jacobian product's bias columns are d delta / d(bias
// estimate); its rows are those of the same error state.
//
// Noise: upstream builds diag(acc_n^2, gyr_n^2, acc_n^2, gyr_n^2, acc_w^2, gyr_w^2) for the
// noises of the two ends of a step and the two bias walks, treated as independent, and
// uses it per step with V's dt factors, never divided by dt: its parameters are per-step
// standard deviations, whatever their name. Per step that gives the rotation a variance
// gyr_n^2 dt^2/2 and a bias gyr_w^2 dt^2. Continuous densities (sigma, sigma_w) give those
// variances, sigma^2 dt and sigma_w^2 dt, with
//   acc_n = sigma_a sqrt(2/dt),  gyr_n = sigma_g sqrt(2/dt),  acc_w = sigma_wa / sqrt(dt),  gyr_w =
//   sigma_wg / sqrt(dt)
// at each step's own dt (VinsNoiseMapping::kFromDensities). kAsConfigured uses the four
// numbers as VINS-Fusion does with the values in its configuration file.
#pragma once

#include <Eigen/Geometry>

#include "imuconv/export.h"
#include "imuconv/preintegrator.h"
#include "imuconv/status.h"
#include "imuconv/types.h"

namespace imuconv::kernels {

/// How the four numbers of ImuNoise become VINS-Fusion's acc_n, gyr_n, acc_w, gyr_w.
enum class VinsNoiseMapping {
  /// The continuous densities, mapped per step so that the covariance is that of continuous
  /// white noise (see above): the one to compare with GTSAM, Basalt or OpenVINS.
  kFromDensities,
  /// The numbers as VINS-Fusion's configuration holds them (acc_n = accel_noise_density,
  /// gyr_n = gyro_noise_density, acc_w = accel_random_walk, gyr_w = gyro_random_walk), used
  /// as upstream uses them: to reproduce a VINS-Fusion run.
  kAsConfigured,
};

/// What IntegrationBase holds after the last push_back.
struct VinsFusionPreintegration {
  double sum_dt = 0.0;
  Vec3 delta_p = Vec3::Zero();
  Eigen::Quaterniond delta_q = Eigen::Quaterniond::Identity();  ///< normalized after every step
  Vec3 delta_v = Vec3::Zero();
  Mat15 jacobian = Mat15::Identity();  ///< product of the steps' F, [p, theta, v, ba, bg]
  Mat15 covariance = Mat15::Zero();    ///< same order and error state
};

/// Integrates the window's knots as IntegrationBase(a_0, w_0, ba, bg) followed by
/// push_back(t_k - t_k-1, a_k, w_k) for every later knot. Checks the input as
/// CheckPreintegrationInput does. Without `jacobians`, only the increment is computed
/// (jacobian stays I and covariance 0): for re-integrations that need the mean alone.
IMUCONV_API Status IntegrateVinsFusion(const PreintegrationInput& in, VinsNoiseMapping mapping,
                                       VinsFusionPreintegration& out, bool jacobians = true);

/// The same, as a native preintegration: covariance in `vins_fusion`, bias Jacobian in the
/// chart of `vins_fusion` (rows [p, theta, v], columns [ba, bg]).
IMUCONV_API Status IntegrateVinsFusion(const PreintegrationInput& in, VinsNoiseMapping mapping,
                                       Preintegrated& out);

/// The increment alone (increment_mean(), imuconv/increment_mean.h: what montecarlo's trials
/// run): IntegrateVinsFusion without its Jacobian product and covariance. The mean's lines are
/// the full path's own, outside its `jacobians` branch, so the increment is the full path's bit
/// for bit; the noise mapping does not enter it.
IMUCONV_API Status VinsFusionIncrementMean(const PreintegrationInput& in, PreintIncrement& delta);

/// The scheme with one noise mapping as a preintegrator's kernel (plugin/kernel_plugin.h):
/// its outputs are in the `vins_fusion` increment convention.
template <VinsNoiseMapping kMapping>
struct VinsFusionScheme {
  static constexpr const char* kCovConvention = "vins_fusion";
  static constexpr const char* kJacobianConvention = "vins_fusion";
  Status operator()(const PreintegrationInput& in, Preintegrated& out) const {
    return IntegrateVinsFusion(in, kMapping, out);
  }
  static Status Mean(const PreintegrationInput& in, PreintIncrement& delta) {
    return VinsFusionIncrementMean(in, delta);
  }
};

}  // namespace imuconv::kernels
