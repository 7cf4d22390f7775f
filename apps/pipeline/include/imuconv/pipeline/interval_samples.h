// Intervals that hold no IMU sample: the rule of docs/timing.md ("Intervals holding no
// sample"), in one place for every path that cuts the samples at keyframes (`imuconv run`'s
// tasks, `imuconv optimize`'s factors, its pipeline task and the Python module).
//
// An interval that holds no sample lies between two samples (or in a gap): integrating over it
// is one interpolated step, and keyframes finer than the samples are almost always a step in
// the wrong unit. A run may mean it (its "allow_empty_intervals"); a preintegration factor
// cannot: over one step the position and velocity increments are driven by the same
// accelerometer noise, so its covariance is singular and the factor cannot be whitened. The
// factor therefore needs a sample strictly inside its interval (two steps at least).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "imuconv/types.h"

namespace imuconv::pipeline {

/// Which samples count as held by [a, b] (each within kSameInstant, window.h, of the end it is
/// compared with).
enum class IntervalEnds {
  kIncluded,  ///< a sample at a or at b counts: at least one step starts or ends on a sample
  kExcluded,  ///< only a sample strictly inside counts: at least two integration steps
};

struct EmptyInterval {
  std::size_t index = 0;  ///< interval k is [time(k), time(k + 1)]
  double t_start = 0.0, t_end = 0.0;
  double median_period = 0.0;  ///< the samples' (MedianPeriod), for the message
};

/// The first interval [time(k), time(k + 1)], k + 1 < count, that lies inside the samples' span
/// (within kSameInstant) and holds no sample under `ends`. Intervals that do not increase or lie
/// outside the data are skipped (the callers report those themselves). One pass over
/// keyframes and samples; `time` is called in increasing k, so generated keyframes need not be
/// stored. Nothing when every interval holds a sample, or there are fewer than two samples.
[[nodiscard]] std::optional<EmptyInterval> FindEmptyInterval(
    const std::vector<ImuSample>& samples, std::size_t count,
    const std::function<double(std::size_t)>& time, IntervalEnds ends);

/// "interval K [A, B] s holds no IMU sample[ strictly inside it]: <what the spacing is>, the IMU
/// period P s (median), so it lies between two samples and is interpolation only (a step in the
/// wrong unit?); N intervals in all", where <what the spacing is> is "the keyframe step is H s"
/// when `step` is given, else "it is B - A s". The callers add what may be done about it.
[[nodiscard]] std::string EmptyIntervalSentence(const EmptyInterval& e, IntervalEnds ends,
                                                std::optional<double> step, std::size_t intervals);

}  // namespace imuconv::pipeline
