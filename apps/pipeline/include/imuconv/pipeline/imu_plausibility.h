// Plausibility of IMU samples' units and column order: warnings with their evidence, never
// errors (a centrifuge, a spacecraft or a spinning projectile may read what a mistake reads).
//
// An IMU on Earth, at rest or in ordinary motion, reads a specific force whose magnitude
// stays near g = 9.81 m/s^2 and angular rates well below that in rad/s. Three common mistakes
// leave clear marks on the median magnitudes over the samples:
// - gyro and accelerometer columns swapped: median |gyro| near 9.81 and median |accel| far
//   from it (nees then fits a noise factor in the thousands and exits 0; a run drifts metres
//   in seconds);
// - accelerometer in g: median |accel| near 1;
// - gyro in deg/s: median |gyro| above 10 rad/s (sustained, not a peak: 573 deg/s if the
//   numbers were rad/s), with the share of samples beyond the +-2000 deg/s (34.9 rad/s) full
//   scale of common MEMS gyros as further evidence.
// And poses read with the samples (ground truth, optimize's poses) must turn as the gyro does:
// PoseGyroWarnings (docs/imu-plausibility.md, "Poses against the gyro").
#pragma once

#include <string>
#include <vector>

#include "imuconv/types.h"

namespace imuconv::pipeline {

struct GroundTruth;  // imuconv/pipeline/imu_reader.h

/// The medians (and what else the warnings quote) of a set of samples.
struct ImuMagnitudes {
  std::size_t count = 0;
  double median_gyro = 0.0;        ///< median |gyro| over the samples (as given, expected rad/s)
  double median_accel = 0.0;       ///< median |accel| (expected m/s^2)
  double beyond_gyro_range = 0.0;  ///< share of samples with |gyro| > 34.9 rad/s (2000 deg/s)
};

ImuMagnitudes MeasureMagnitudes(const std::vector<ImuSample>& samples);

/// One sentence per suspected mistake, naming `source` (a file, "inline", ...) and the
/// evidence: "SOURCE: the gyro and accelerometer columns look swapped: median |gyro| 9.807,
/// median |accel| 0.0123 over 2000 samples; ...". Empty when nothing is suspicious or there
/// are fewer than kMinSamples samples (a median of a handful says little). Work and memory:
/// one copy of the magnitudes, O(n).
std::vector<std::string> ImuPlausibilityWarnings(const std::vector<ImuSample>& samples,
                                                 const std::string& source);

inline constexpr std::size_t kPlausibilityMinSamples = 20;

/// Whether `poses`' rotations agree with the gyro's: over non-overlapping windows of 0.5 s
/// between poses (within the samples' span), the rotation vector of the poses' relative rotation
/// Log(R_i^T R_j) against that of the gyro's integrated rotation (the product of Exp(w dt)),
/// after the best constant rotation between the two frames and a constant offset (the gyro
/// bias times the window) are fitted: what is left is the windows' residual. One sentence
/// naming `poses_name` with the median residual, the median rotation and the number of windows
/// when that median exceeds 0.02 rad; empty when it does not, and when fewer than 20 windows
/// turn by more than 0.05 rad (no judgment without rotation). Work: O(samples + poses).
std::vector<std::string> PoseGyroWarnings(const std::vector<ImuSample>& samples,
                                          const GroundTruth& poses, const std::string& poses_name);

}  // namespace imuconv::pipeline
