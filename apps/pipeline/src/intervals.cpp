// Keyframes from {start, end, step}, generated on demand (nothing stored per keyframe).
#include <algorithm>
#include <cmath>

#include "intervals.h"

namespace imuconv::pipeline {
namespace {

// A remainder of (end - start) / step below this fraction of a step is round-off of the
// division (20 / 0.1 = 200.00000000000003), not an interval of its own: `end` then replaces
// the last whole step's keyframe.
constexpr double kStepRoundOff = 1e-9;

double Snapped(double t) {
  // a + k h, snapped to the nearest nanosecond when that is within round-off (0.1 * 3 -> 0.3).
  const double snapped = std::round(t * 1e9) / 1e9;
  return std::abs(snapped - t) <= 1e-12 * std::max(1.0, std::abs(t)) ? snapped : t;
}

}  // namespace

double IntervalsSpec::time(std::size_t k) const {
  if (form != Form::Generated) return times[k];
  if (k + 1 == count) return end;
  return Snapped(start + static_cast<double>(k) * step);
}

std::string IntervalsSpec::pointer_of(std::size_t k) const {
  switch (form) {
    case Form::Interval: return pointer + (k == 0 ? "/t_start" : "/t_end");
    case Form::Array: return pointer + "/" + std::to_string(k);
    case Form::Generated: break;
  }
  if (k == 0) return pointer + "/start";
  if (k + 1 == count) return pointer + "/end";
  return pointer;
}

std::optional<std::string> GenerateKeyframes(double a, double b, double h, IntervalsSpec& iv) {
  const double q = (b - a) / h;
  if (!(q <= static_cast<double>(kMaxKeyframes)))
    return std::string("step gives more than 1e7 keyframes (the limit of one task)");
  double n = std::floor(q);
  if (q - n >= 1.0 - kStepRoundOff) n += 1.0;  // just below a whole number of steps
  const double frac = q - n;                     // in [-kStepRoundOff, 1 - kStepRoundOff)
  if (n < 1.0) return std::string("step is longer than end - start: not one whole step between start and end");
  iv.form = IntervalsSpec::Form::Generated;
  iv.start = a;
  iv.step = h;
  iv.end = b;
  iv.short_last = frac > kStepRoundOff;
  iv.count = static_cast<std::size_t>(n) + (iv.short_last ? 2 : 1);
  // Steps near the resolution of double at these times could make keyframes coincide.
  for (std::size_t k = 1; k < iv.count; ++k)
    if (!(iv.time(k) > iv.time(k - 1)))
      return "step is too small to tell keyframes " + std::to_string(k - 1) + " and " + std::to_string(k) + " apart";
  return std::nullopt;
}

}  // namespace imuconv::pipeline
