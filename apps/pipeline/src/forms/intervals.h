// The intervals a task integrates over (internal to imuconv_pipeline):
//   "interval": {"t_start", "t_end"}                 one interval
//   "keyframes": [t0, t1, ...]                        consecutive keyframe pairs
//   "keyframes": {"start", "end", "step"}             generated on demand
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "imuconv/pipeline/json_check.h"

namespace imuconv::pipeline {

/// The most keyframes one task may ask for (array or generated).
constexpr std::size_t kMaxKeyframes = 10000000;

/// Interval boundaries: one interval [t0, t1] or consecutive keyframe pairs. Explicit times
/// ("interval", a keyframes array) are stored; a generated {start, end, step} form is not
/// (a tiny step must not cost memory per keyframe): its keyframes are start + k step and,
/// last, `end` itself. A remainder of (end - start) shorter than a step, beyond round-off
/// (1e-9 of a step), is a last, shorter interval ending at `end`.
struct IntervalsSpec {
  enum class Form { Interval, Array, Generated } form = Form::Interval;
  std::vector<double> times;            // Interval, Array
  double start = 0, step = 0, end = 0;  // Generated
  std::size_t count = 0;                // Generated: number of keyframes
  bool short_last = false;              // Generated: the last interval is a remainder
  std::string pointer;                  // the "interval" or "keyframes" node

  std::size_t size() const { return form == Form::Generated ? count : times.size(); }
  /// Keyframe k (k < size()).
  double time(std::size_t k) const;
  double front() const { return time(0); }
  double back() const { return time(size() - 1); }
  /// The pointer of keyframe k, for messages: its own for explicit times, start or end
  /// (or the keyframes object, for an interior one) for the generated form.
  std::string pointer_of(std::size_t k) const;
};

/// Makes `iv` the generated keyframes start + k step up to `end` (end > start, step > 0):
/// `end` is always the last keyframe; a remainder shorter than a step (beyond round-off) is
/// a last, shorter interval. Returns what is wrong instead (too many keyframes, not one
/// whole step, keyframes too close to tell apart), for the step's pointer.
std::optional<std::string> GenerateKeyframes(double start, double end, double step,
                                             IntervalsSpec& iv);

/// "interval" and, when `allow_keyframes`, "keyframes" of `task` (exactly one of them).
std::optional<IntervalsSpec> ReadIntervals(const Node& task, bool allow_keyframes);

}  // namespace imuconv::pipeline
