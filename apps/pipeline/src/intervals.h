// Keyframes from {start, end, step} (internal to imuconv_pipeline; IntervalsSpec is in spec.h).
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "spec.h"

namespace imuconv::pipeline {

/// The most keyframes one task may ask for (array or generated).
constexpr std::size_t kMaxKeyframes = 10000000;

/// Makes `iv` the generated keyframes start + k step up to `end` (end > start, step > 0):
/// `end` is always the last keyframe; a remainder shorter than a step (beyond round-off) is
/// a last, shorter interval. Returns what is wrong instead (too many keyframes, not one
/// whole step, keyframes too close to tell apart), for the step's pointer.
std::optional<std::string> GenerateKeyframes(double start, double end, double step, IntervalsSpec& iv);

}  // namespace imuconv::pipeline
