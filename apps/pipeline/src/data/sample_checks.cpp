// The one set of checks on IMU samples (imuconv/pipeline/sample_checks.h).
#include "imuconv/pipeline/sample_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace imuconv::pipeline {
namespace {

std::string SampleNum(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

// The unit 1000x finer (finer = true) or coarser than u, if there is one.
std::optional<TimeUnit> Neighbour(TimeUnit u, bool finer) {
  switch (u) {
    case TimeUnit::s:
      return finer ? std::optional<TimeUnit>(TimeUnit::ms) : std::nullopt;
    case TimeUnit::ms:
      return finer ? TimeUnit::us : TimeUnit::s;
    case TimeUnit::us:
      return finer ? TimeUnit::ns : TimeUnit::ms;
    case TimeUnit::ns:
      return finer ? std::nullopt : std::optional<TimeUnit>(TimeUnit::us);
  }
  return std::nullopt;
}

}  // namespace

std::optional<SampleIssue> FindSampleIssue(const std::vector<ImuSample>& s,
                                           const TimingPolicy& policy, TimeUnit declared,
                                           TimeSource source) {
  static const char* const kNames[7] = {"t", "wx", "wy", "wz", "ax", "ay", "az"};
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double v[7] = {s[k].t,        s[k].gyro[0],  s[k].gyro[1], s[k].gyro[2],
                         s[k].accel[0], s[k].accel[1], s[k].accel[2]};
    for (int j = 0; j < 7; ++j)
      if (!std::isfinite(v[j]))
        return SampleIssue{k, std::string(kNames[j]) + " is not finite (" + SampleNum(v[j]) + ")"};
    if (k > 0 && !(s[k].t > s[k - 1].t))
      return SampleIssue{k, "time must increase strictly: t = " + SampleNum(s[k].t) + " s after " +
                                SampleNum(s[k - 1].t) + " s"};
  }
  std::vector<double> t(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) t[k] = s[k].t;
  const auto issue = FindTimingIssue(t, policy, declared, source);
  if (!issue) return std::nullopt;
  if (issue->kind == TimingIssue::Kind::gap) return SampleIssue{issue->index, issue->message};
  return SampleIssue{std::nullopt, issue->message};
}

std::optional<std::string> FindNoiseIssue(const ImuNoise& q, double shortest_period) {
  const std::pair<const char*, double> fields[] = {{"gyro_noise_density", q.gyro_noise_density},
                                                   {"accel_noise_density", q.accel_noise_density},
                                                   {"gyro_random_walk", q.gyro_random_walk},
                                                   {"accel_random_walk", q.accel_random_walk}};
  for (const auto& [name, value] : fields) {
    if (!std::isfinite(value) || value < 0.0)
      return std::string(name) + ": expected a finite number >= 0, got " + SampleNum(value);
    // The discrete covariance of one step is density^2 / dt (white noise) or density^2 x dt
    // (random walk); the larger of the two must be a number for the sums to stay finite.
    const double per_step = value * value * std::max(1.0 / shortest_period, shortest_period);
    if (std::isfinite(shortest_period) && shortest_period > 0.0 && !std::isfinite(per_step))
      return std::string(name) + " = " + SampleNum(value) +
             " is too large: its square over the sample period (" + SampleNum(shortest_period) +
             " s) is not a finite number, so every covariance would be inf";
  }
  return std::nullopt;
}

std::optional<std::string> FindRateDisagreement(double imu_period, double gt_period,
                                                TimeUnit declared, TimeSource source) {
  if (!(imu_period > 0.0) || !(gt_period > 0.0) || !std::isfinite(imu_period) ||
      !std::isfinite(gt_period))
    return std::nullopt;
  const double ratio = gt_period / imu_period;  // IMU rate / ground-truth rate
  if (ratio >= kMinImuToGroundTruthRate && ratio <= kMaxImuToGroundTruthRate) return std::nullopt;
  // Too slow an IMU: its stamps were read 1000x too large, i.e. they are in a finer unit.
  const bool finer = ratio < kMinImuToGroundTruthRate;
  std::string m = "the IMU's median period is " + SampleNum(imu_period) + " s (" +
                  SampleNum(1.0 / imu_period) + " Hz) but the ground truth's is " +
                  SampleNum(gt_period) + " s (" + SampleNum(1.0 / gt_period) +
                  " Hz): the IMU would be " + SampleNum(ratio) +
                  " times as fast as the ground truth (expected 10^-1.5 to 10^2.5, a wrong time "
                  "unit moves it by 10^3); ";
  const auto likely = Neighbour(declared, finer);
  if (source == TimeSource::imu_euroc)
    return m + "the EuRoC format reads nanoseconds: check the IMU file's timestamps" +
           (likely ? std::string(" (they look like ") + TimeUnitName(*likely) + ")"
                   : std::string());
  if (!likely)
    return m + "no other time unit fits: check the IMU's time column and the ground truth";
  return m + "the IMU's timestamps look like " + TimeUnitName(*likely) + ", not " +
         TimeUnitName(declared) + ": set time_unit to \"" + TimeUnitName(*likely) + "\"";
}

}  // namespace imuconv::pipeline
