// The input of a preintegration, as the tests form it: a window of samples at a bias estimate,
// with a noise model. PreintegrationInput is filled field by field in one place, so that every
// test gives all four and none leaves one at its default unnoticed.
#pragma once

#include "imuconv/preintegrator.h"

namespace imuconv::test {

/// `window` at the bias estimate (bg, ba), with `noise`. The window references its samples:
/// they must outlive the input.
inline PreintegrationInput PreintegrationInputOf(const SampleWindow& window, const Vec3& bg,
                                                 const Vec3& ba, const ImuNoise& noise) {
  PreintegrationInput in;
  in.bg = bg;
  in.ba = ba;
  in.noise = noise;
  in.window = window;
  return in;
}

}  // namespace imuconv::test
