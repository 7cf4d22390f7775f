// Time units, and the checks on the timing of a series of samples: an implausible rate
// (usually a wrong time unit) and gaps that would otherwise be interpolated across in silence.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace imuconv::pipeline {

enum class TimeUnit { s, ms, us, ns };
/// Nanoseconds per unit: 1e9, 1e6, 1e3, 1.
std::int64_t NanosPerUnit(TimeUnit u);
const char* TimeUnitName(TimeUnit u);
[[nodiscard]] std::optional<TimeUnit> ParseTimeUnit(const std::string& s);

/// Plausible sample rates, in Hz. IMUs run from a few Hz (phones in power saving) to tens of
/// kHz (vibration sensors); outside this range the time unit is almost certainly wrong.
inline constexpr double kMinRateHz = 1.0;
inline constexpr double kMaxRateHz = 1.0e5;

/// What to do about gaps between consecutive samples (IMU) or rows (ground truth).
struct TimingPolicy {
  /// A gap longer than max_gap_factor x the median period is an error. Must be finite and
  /// >= 1 (the JSON layer checks it; a value outside that is treated as the default, 10).
  double max_gap_factor = 10;
  /// Gaps are not checked (the rate check still runs).
  bool allow_gaps = false;
};

struct ReadOptions {
  TimingPolicy timing;
  /// [t0, t1], seconds relative to the data's origin (the axis of ImuData::samples[i].t and
  /// GroundTruth::t): the reader keeps only the samples inside, plus one on each side (for
  /// interpolation at t0 and t1). Every line is still read and validated. Nothing: keep all.
  std::optional<std::pair<double, double>> keep;
};

/// Where a series of times comes from; decides the advice given in messages.
enum class TimeSource {
  imu,           ///< generic CSV or inline samples: the user chooses "time_unit"
  imu_euroc,     ///< EuRoC IMU file: always integer nanoseconds
  ground_truth,  ///< EuRoC / vicon2gt ground truth: always integer nanoseconds
  imu_array,     ///< the Python module's sample arrays: seconds, no time_unit to set
};

struct TimingIssue {
  enum class Kind { gap, rate };
  Kind kind = Kind::gap;
  /// gap: the index of the sample after the gap; rate: 0 (the problem is the whole series).
  std::size_t index = 0;
  /// The sentence, without a file, line or pointer in front.
  std::string message;
  /// The numbers it states (for callers that word their own advice): the median period; for
  /// a gap, the gap and the limit it exceeds (max_gap_factor x median), all in seconds.
  double median_period = 0.0;
  double gap = 0.0;
  double limit = 0.0;
};

/// The lower median of the periods t[i+1] - t[i] (0 if t has fewer than 2 entries). The lower
/// median, so that with few samples one long gap cannot become the reference it is judged by.
double MedianPeriod(const std::vector<double>& t);

/// Checks strictly increasing times `t` (seconds), read in `declared` units: first the rate
/// (the median period must give kMinRateHz..kMaxRateHz, else the message names the unit the
/// stamps look like), then, unless policy.allow_gaps, every gap against
/// policy.max_gap_factor x the median period. Nothing if the series is fine or has < 2 samples.
std::optional<TimingIssue> FindTimingIssue(const std::vector<double>& t, const TimingPolicy& policy,
                                           TimeUnit declared = TimeUnit::s,
                                           TimeSource source = TimeSource::imu);

/// The same with the median period given (the readers take it from a window around the kept
/// range, see imu_reader.h).
std::optional<TimingIssue> FindTimingIssue(const std::vector<double>& t, double median_period,
                                           const TimingPolicy& policy, TimeUnit declared,
                                           TimeSource source);

}  // namespace imuconv::pipeline
