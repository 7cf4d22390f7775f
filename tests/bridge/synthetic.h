// A deterministic smooth IMU sequence for the bridge tests (sums of sinusoids, 200 Hz).
#pragma once

#include <cmath>
#include <vector>

#include "imuconv/types.h"

namespace imuconv::test {

inline std::vector<ImuSample> SmoothImu(double duration, double rate = 200.0, double t0 = 10.0) {
  std::vector<ImuSample> s;
  const int n = static_cast<int>(std::lround(duration * rate)) + 1;
  for (int k = 0; k < n; ++k) {
    const double t = k / rate;
    ImuSample z;
    z.t = t0 + t;
    z.gyro = Vec3(0.5 * std::sin(1.3 * t + 0.2), -0.4 * std::cos(0.7 * t), 0.3 * std::sin(2.1 * t + 1.0)) +
             Vec3(0.01, -0.02, 0.015);
    z.accel = Vec3(1.5 * std::cos(0.9 * t), 2.0 * std::sin(1.7 * t + 0.3), 9.81 + 0.8 * std::sin(0.5 * t)) +
              Vec3(0.05, 0.1, -0.08);
    s.push_back(z);
  }
  return s;
}

inline ImuNoise TestNoise() {
  // gyro and accelerometer noise densities, then gyro and accelerometer random walks
  return ImuNoise{2e-3, 3e-2, 4e-4, 6e-3};
}

}  // namespace imuconv::test
