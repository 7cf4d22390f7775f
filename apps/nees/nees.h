// imuconv nees: the consistency of a propagator's covariance on real data. For each window
// length L, windows [t, t + L] start every `stride` seconds along the data; each starts at the
// ground-truth state (with its biases) and zero covariance, is propagated with one propagator in
// one state convention, and its end state is compared with the ground truth at t + L:
//   e = [p, theta, v] blocks of local_C(x_gt, x_pred),  NEES = e^T P^-1 e,
// P the propagated covariance's [p, theta, v] marginal (9x9). If the noise model were right,
// each NEES would be chi-square with 9 dof.
//
// The factor: scaling all four noise densities by k scales the continuous noise covariance by
// k^2, and with a zero start covariance the propagated covariance is linear in it,
// P(k) = k^2 P(1) (the recursion P+ = F P F^T + G Q G^T with F independent of the noise), so
// NEES(k) = NEES(1) / k^2 for every window. The k that puts the median NEES on the chi-square(9)
// median is therefore k = sqrt(median NEES(1) / chi2_9(0.5)), in closed form (docs/nees.md).
// The same linearity splits each window's covariance into a gyro part and an accelerometer part,
// and two factors, one per sensor, are fitted on the theta and v blocks (split_factors.h); each
// error component's offset is judged under them (error_components.h).
#pragma once

#include <string>
#include <vector>

#include "error_components.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/registry.h"

namespace imuconv::nees {

/// Degrees of freedom of the error [p, theta, v].
constexpr int kDof = 9;
/// Two-sided confidence of the per-window bounds.
constexpr double kConfidence = 0.95;

/// Most windows of one run, all the window lengths together (--stride small against the data's
/// span; the reason for the number is at its check, nees.cpp).
constexpr std::size_t kMaxWindows = 1000000;

/// The chi-square(9) figures the report is judged against (imuconv/chi_square.h, exact).
struct ChiSquareReference {
  double median = 0.0;
  double lower = 0.0;  ///< the (1 - kConfidence) / 2 quantile
  double upper = 0.0;  ///< the (1 + kConfidence) / 2 quantile
};
ChiSquareReference ChiSquare9();

struct Options {
  std::string method;                  ///< a propagator id
  std::string convention = "left";     ///< a state convention id
  std::vector<double> window_lengths;  ///< seconds, each > 0
  double stride = 0.0;                 ///< seconds between window starts; 0: each window's length
  ImuNoise noise;
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
};

/// One window length's windows and their statistics.
struct WindowLengthResult {
  double length = 0.0;
  double stride = 0.0;
  /// Windows reaching into a gap of the data (samples more than 10 median periods apart),
  /// skipped, not fitted; the start of the first of them. The statistics are over the others.
  std::size_t skipped_in_gap = 0;
  double first_skipped = 0.0;
  std::vector<double> t_start;  ///< seconds relative to the IMU data's origin
  std::vector<double> nees;     ///< one per window, in the order of t_start
  /// Per window: the end error [p, theta, v] (the chart's local coordinates of the propagated
  /// state about the ground truth) and the square roots of the diagonal of its propagated
  /// covariance under the declared densities. (Empty in a result built by hand without them: the
  /// report then leaves out the error time series.)
  std::vector<Vec9> error, sigma;
  /// Per window: the [p, theta, v] marginal of the covariance propagated with the gyro densities
  /// alone (P_g) and with the accelerometer densities alone (P_a); P_g + P_a is the declared
  /// densities' covariance (split_factors.h).
  std::vector<Mat9> cov_gyro, cov_accel;
  double median = 0.0, mean = 0.0, p95 = 0.0;
  double fraction_inside = 0.0;  ///< of the NEES values within [lower, upper] of ChiSquare9()
  double factor = 0.0;  ///< k = sqrt(median / chi2_9 median), one scale on all four densities
  /// The two factors of split_factors.h; NaN when undefined (a sensor's densities are zero).
  double factor_gyro = 0.0, factor_accel = 0.0;
  /// The nine components under k_gyro^2 P_g + k_accel^2 P_a (empty when a factor is NaN).
  std::vector<ComponentStatistics> components;
};

struct Result {
  std::string method, convention;
  ImuNoise noise;
  ChiSquareReference chi2;
  double t_begin = 0.0,
         t_end = 0.0;  ///< the span covered by both the IMU data and the ground truth
  std::vector<WindowLengthResult> windows;
};

/// Runs every window length. Throws Error for an unknown method or convention, noise densities
/// that are all zero, a window longer than the span the IMU data and the ground truth share or
/// shorter than the IMU's median sample period, more than kMaxWindows windows in all, a window
/// holding no IMU sample between two ordinary samples, a length all of whose windows reach into
/// a gap, or a propagated covariance that is not positive definite. A window reaching into a
/// gap of the samples (more than 10 median periods apart) is skipped and counted.
Result RunNees(const Registry& reg, const pipeline::ImuData& imu, const pipeline::GroundTruth& gt,
               const Options& options);

}  // namespace imuconv::nees
