// Intervals and keyframes, read; keyframes from {start, end, step} generated on demand
// (nothing stored per keyframe).
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
    case Form::Interval:
      return pointer + (k == 0 ? "/t_start" : "/t_end");
    case Form::Array:
      return pointer + "/" + std::to_string(k);
    case Form::Generated:
      break;
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
  const double frac = q - n;                   // in [-kStepRoundOff, 1 - kStepRoundOff)
  if (n < 1.0)
    return std::string("step is longer than end - start: not one whole step between start and end");
  iv.form = IntervalsSpec::Form::Generated;
  iv.start = a;
  iv.step = h;
  iv.end = b;
  iv.short_last = frac > kStepRoundOff;
  iv.count = static_cast<std::size_t>(n) + (iv.short_last ? 2 : 1);
  // Steps near the resolution of double at these times could make keyframes coincide.
  for (std::size_t k = 1; k < iv.count; ++k)
    if (!(iv.time(k) > iv.time(k - 1)))
      return "step is too small to tell keyframes " + std::to_string(k - 1) + " and " +
             std::to_string(k) + " apart";
  return std::nullopt;
}

/// "interval": {"t_start", "t_end"} and/or "keyframes": [...] | {"start","end","step"}.
std::optional<IntervalsSpec> ReadIntervals(const Node& task, bool allow_keyframes) {
  const bool has_i = task.has("interval"), has_k = task.has("keyframes");
  if (!allow_keyframes && has_k) return std::nullopt;  // reported as an unknown key
  if (has_i && has_k) {
    task.checker().error(task.child_pointer("keyframes"),
                         "give either \"interval\" or \"keyframes\", not both");
    return std::nullopt;
  }
  if (!has_i && !has_k) {
    task.checker().error(task.child_pointer("interval"),
                         allow_keyframes
                             ? "required key is missing (give \"interval\" or \"keyframes\")"
                             : "required key is missing");
    return std::nullopt;
  }
  IntervalsSpec iv;
  if (has_i) {
    const Node in = task["interval"];
    iv.pointer = in.pointer();
    if (!in.expect_object({"t_start", "t_end"})) return std::nullopt;
    const auto ts = in.number("t_start", true);
    const auto te = in.number("t_end", true);
    if (!ts || !te) return std::nullopt;
    if (!(*te > *ts)) {
      in.checker().error(in.child_pointer("t_end"), "t_end must be after t_start");
      return std::nullopt;
    }
    iv.form = IntervalsSpec::Form::Interval;
    iv.times = {*ts, *te};
    return iv;
  }
  const Node kn = task["keyframes"];
  iv.pointer = kn.pointer();
  if (kn.is_array()) {
    if (kn.size() < 2) {
      kn.fail("expected at least 2 keyframe times");
      return std::nullopt;
    }
    if (kn.size() > kMaxKeyframes) {
      kn.fail("too many keyframes (more than 1e7, the limit of one task)");
      return std::nullopt;
    }
    auto ts = kn.number_list(2);
    if (!ts) return std::nullopt;
    for (std::size_t i = 1; i < ts->size(); ++i)
      if (!((*ts)[i] > (*ts)[i - 1])) {
        kn[i].fail("keyframe times must be strictly increasing");
        return std::nullopt;
      }
    iv.form = IntervalsSpec::Form::Array;
    iv.times = std::move(*ts);
    return iv;
  }
  if (kn.is_object()) {
    kn.expect_object({"start", "end", "step"});
    const auto a = kn.number("start", true), b = kn.number("end", true),
               h = kn.number("step", true);
    if (!a || !b || !h) return std::nullopt;
    if (!(*h > 0.0)) {
      kn.checker().error(kn.child_pointer("step"), "expected a positive step");
      return std::nullopt;
    }
    if (!(*b > *a)) {
      kn.checker().error(kn.child_pointer("end"), "end must be after start");
      return std::nullopt;
    }
    if (auto problem = GenerateKeyframes(*a, *b, *h, iv)) {
      kn.checker().error(kn.child_pointer("step"), *problem);
      return std::nullopt;
    }
    return iv;
  }
  kn.fail("expected an array of keyframe times or {\"start\", \"end\", \"step\"}, found " +
          TypeName(kn.value()));
  return std::nullopt;
}

}  // namespace imuconv::pipeline
