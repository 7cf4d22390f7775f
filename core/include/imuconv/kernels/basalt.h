// Basalt's preintegration (basalt-headers, IntegratedImuMeasurement with
// propagateState), reproduced to round-off: the delta state, its 9x9 covariance and the
// two 9x3 bias Jacobians, in its own delta-state perturbation.
//
// One step over dt with the held sample's bias-corrected a, w:
//   R_half = R Exp(w dt/2),  a_w = R_half a,
//   R' = R Exp(w dt),  v' = v + a_w dt,  p' = p + v dt + a_w dt^2/2.
// Basalt's times are integer nanoseconds (t_ns = llround(t 1e9)); dt = (t_ns' - t_ns) 1e-9.
//
// Error state `basalt`, order [p, theta, v] (its [trans, rot, vel]): p = p^ + dp,
// R = Exp(dtheta) R^ (LEFT, as PoseVelState::applyInc), v = v^ + dv. Its step Jacobians:
//   F = [I  F_pt  I dt; 0 I 0; 0 F_vt I] with F_vt = [-a_w dt]x, F_pt = F_vt dt/2,
//   A = d x'/d a = [R_half dt^2/2; 0; R_half dt],
//   G = d x'/d w = [G_v dt/2; R' Jr(w dt) dt; G_v],  G_v = [-a_w dt]x R_half Jr(w dt/2) dt/2,
// and cov' = F cov F^T + A diag(accel_cov) A^T + G diag(gyro_cov) G^T,
// d_state_d_ba' = -A + F d_state_d_ba, d_state_d_bg' = -G + F d_state_d_bg.
//
// Which sample is held over a step (the window's knots j, j+1):
//   kNative:     knot j+1, held over (t_j, t_j+1]: what Basalt's VIO does, each sample
//                integrated with its own timestamp (the interval's first knot unused);
//   kForwardZoh: knot j, held over [t_j, t_j+1]: GTSAM's zero-order hold.
//
// Noise: integrate() takes per-sample variances; Basalt's VIO passes its calibration's
// densities times the nominal imu_update_rate (dicrete_time_*_noise_std()^2 = sigma^2 f).
// With BasaltSampleVariances unset the kernel uses sigma^2 / dt at each step's own dt, which
// is that on regularly sampled data and the continuous-noise covariance on any. Basalt's
// 9x9 covariance has no bias random walk: its VIO weights the bias change with separate
// random-walk factors, independent of the preintegration.
#pragma once

#include <optional>

#include "imuconv/export.h"
#include "imuconv/preintegrator.h"
#include "imuconv/status.h"
#include "imuconv/types.h"

namespace imuconv::kernels {

enum class BasaltFeeding { kNative, kForwardZoh };

/// How a preintegrator reads the four noise numbers:
///   kFromDensities: continuous densities, per-sample variances sigma^2 / dt at each step's dt;
///   kAsConfigured:  gyro_noise_density and accel_noise_density are the per-sample standard
///                   deviations Basalt's integrate() is given (its VIO's
///                   dicrete_time_*_noise_std(), sigma_c sqrt(imu_update_rate)), constant over
///                   steps whatever their dt, as Basalt uses them; the random walks stay densities.
enum class BasaltNoiseMapping { kFromDensities, kAsConfigured };

/// The per-sample variances Basalt's integrate() is given (per axis).
struct BasaltSampleVariances {
  Vec3 accel = Vec3::Zero(), gyro = Vec3::Zero();
};

/// What IntegratedImuMeasurement holds after the last integrate().
struct BasaltPreintegration {
  long long dt_ns = 0;
  Mat3 R = Mat3::Identity();
  Vec3 p = Vec3::Zero(), v = Vec3::Zero();
  Mat9 cov = Mat9::Zero();  ///< [p, theta, v], left rotation error
  Eigen::Matrix<double, 9, 3> d_state_d_ba = Eigen::Matrix<double, 9, 3>::Zero(),
                              d_state_d_bg = Eigen::Matrix<double, 9, 3>::Zero();
};

/// Integrates the window's knots as IntegratedImuMeasurement(t_0, bg, ba) with one
/// integrate() per step, fed as `feeding` says; `variances` as Basalt's caller gives them,
/// or, unset, the densities of in.noise over each step's dt. Checks the input as
/// CheckPreintegrationInput does, and that every step is at least 1 ns. Without
/// `jacobians`, only the delta state is computed (covariance and bias Jacobians stay 0).
IMUCONV_API Status IntegrateBasalt(const PreintegrationInput& in, BasaltFeeding feeding,
                                   const std::optional<BasaltSampleVariances>& variances,
                                   BasaltPreintegration& out, bool jacobians = true);

/// The same as a native preintegration (densities over each step's dt): covariance and bias
/// Jacobian in `basalt` ([p, theta, v, bg, ba]); the bias blocks of the covariance are the
/// random walks over the interval, sigma_b^2 T, uncorrelated with the rest, as Basalt's
/// separate random-walk factors model them.
IMUCONV_API Status IntegrateBasalt(const PreintegrationInput& in, BasaltFeeding feeding,
                                   Preintegrated& out,
                                   BasaltNoiseMapping noise = BasaltNoiseMapping::kFromDensities);

/// The scheme with one feeding as a preintegrator's kernel (plugin/kernel_plugin.h): its
/// outputs are in the `basalt` increment convention.
template <BasaltFeeding kFeeding, BasaltNoiseMapping kNoise = BasaltNoiseMapping::kFromDensities>
struct BasaltScheme {
  static constexpr const char* kCovConvention = "basalt";
  static constexpr const char* kJacobianConvention = "basalt";
  Status operator()(const PreintegrationInput& in, Preintegrated& out) const {
    return IntegrateBasalt(in, kFeeding, out, kNoise);
  }
};

}  // namespace imuconv::kernels
