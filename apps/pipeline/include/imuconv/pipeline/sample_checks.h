// The checks every series of IMU samples gets before it is integrated, on every path: the
// pipeline's inline samples and readers, `imuconv check` cases, and the Python module's
// arrays. One rule, so that an input the command line refuses is refused by Python too, with
// the same sentence.
//
// What is checked: every number finite; time strictly increasing; the rate and the gaps of
// timing.h (FindTimingIssue); the noise densities usable (their squares over the shortest
// period finite, the covariance the kernels accumulate); and, when the ground truth's rate is
// known, that the IMU's rate agrees with it to within the margin a wrong time unit (a factor
// of 10^3) cannot stay inside.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "imuconv/pipeline/timing.h"
#include "imuconv/types.h"

namespace imuconv::pipeline {

struct SampleIssue {
  /// The sample the problem is at (the one after a gap, the first non-finite or
  /// non-increasing one), or nothing when it concerns the whole series (the rate).
  std::optional<std::size_t> index;
  /// The sentence, without a file, line or pointer in front.
  std::string message;
};

/// Finite numbers, strictly increasing t, then FindTimingIssue(t, policy, declared, source).
/// Nothing when the series is fine.
[[nodiscard]] std::optional<SampleIssue> FindSampleIssue(const std::vector<ImuSample>& samples,
                                                         const TimingPolicy& policy,
                                                         TimeUnit declared, TimeSource source);

/// The noise densities must be finite and >= 0, and their squares divided by
/// `shortest_period` (seconds, the shortest sample period; the discrete covariance of one
/// step) finite: 1e160 passes the first test and turns every covariance into inf.
[[nodiscard]] std::optional<std::string> FindNoiseIssue(const ImuNoise& noise,
                                                        double shortest_period);

/// An IMU is as fast as the motion capture it is compared with, or up to some ten times
/// faster (EuRoC: 200 Hz and 200 Hz; TUM VI: 200 Hz and 120 Hz; phones: 100-400 Hz against
/// 100 Hz). A rate ratio imu/ground truth outside [10^-1.5, 10^2.5] (3 decades wide, centred
/// on a factor 3) is what a wrong time unit gives: a unit slip moves the ratio by 10^3, out of
/// a band of that width whatever the true ratio was. The rate check alone cannot see it: a
/// 1 kHz IMU with millisecond stamps read as seconds is a 1 Hz IMU, inside 1 Hz..100 kHz.
inline constexpr double kMinImuToGroundTruthRate = 0.031622776601683794;  // 10^-1.5
inline constexpr double kMaxImuToGroundTruthRate = 316.22776601683796;    // 10^2.5

/// Compares the median periods of the IMU samples and of the ground truth (seconds, both
/// positive). Nothing when the rates agree (see above); else the sentence, naming the unit the
/// IMU's stamps would then be in.
[[nodiscard]] std::optional<std::string> FindRateDisagreement(double imu_period,
                                                              double ground_truth_period,
                                                              TimeUnit declared, TimeSource source);

}  // namespace imuconv::pipeline
