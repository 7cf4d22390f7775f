// The smooth synthetic motion the benchmark programs integrate: every axis of both sensors
// excited, gravity on z, the same at any rate (a sample is a function of its time alone).
#pragma once

#include <cmath>

#include "imuconv/types.h"

namespace imuconv::bench {

/// The sample at `t` seconds into the motion, stamped `stamp` (a program may shift its axis).
inline ImuSample SyntheticSample(double t, double stamp) {
  ImuSample z;
  z.t = stamp;
  z.gyro =
      Vec3(0.5 * std::sin(1.3 * t + 0.2), -0.4 * std::cos(0.7 * t), 0.3 * std::sin(2.1 * t + 1.0));
  z.accel =
      Vec3(1.5 * std::cos(0.9 * t), 2.0 * std::sin(1.7 * t + 0.3), 9.81 + 0.8 * std::sin(0.5 * t));
  return z;
}

}  // namespace imuconv::bench
