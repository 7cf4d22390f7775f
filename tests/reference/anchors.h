// What the tests against other systems' own numbers (tests/data/reference/anchors) share:
// the bounds and the anchors' construction of the preintegration input.
//
// The bound on every computed field is the anchors' 1e-8 by the metric of J. Huai, "IMU
// Propagation as Preintegration" (relative above 1e-4, absolute below): the same scheme
// computed in another order (and here with FMA, upstream without) differs by rounding only,
// accumulated over 2000 steps. The metric leaves entries below 1e-4 unchecked, so covariances
// are also compared on the correlation scale and Jacobians relative to each entry above a
// floor of 1e-4 of the largest (scale_aware.h), at 1e-9: a sign or a factor in any block
// gives O(1) there.
#pragma once

#include "../integrators/integrator_cases.h"
#include "imuconv/preintegrator.h"

namespace imuconv::test {

constexpr double kAnchorMetricTol = 1e-8;
constexpr double kAnchorScaledTol = 1e-9;

/// The preintegration anchors' input: the whole case from its first sample to its last, at
/// the bias estimate given (the case's start biases, or a changed one).
inline PreintegrationInput AnchorInput(const ImuCase& c, const Vec3& bg, const Vec3& ba) {
  PreintegrationInput in;
  in.window = MakeInput(c, c.samples.front().t, c.samples.back().t).window;
  in.bg = bg;
  in.ba = ba;
  in.noise = c.noise;
  return in;
}

}  // namespace imuconv::test
