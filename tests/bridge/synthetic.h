// A deterministic smooth IMU sequence for the bridge tests (sums of sinusoids, 200 Hz), its
// noise, and the scenario the prediction and residual tests share: 1 s of it as one window and
// a start state far from the identity with nonzero biases.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "imuconv/so3.h"
#include "imuconv/types.h"
#include "imuconv/window.h"

namespace imuconv::test {

inline std::vector<ImuSample> SmoothImu(double duration, double rate = 200.0, double t0 = 10.0) {
  std::vector<ImuSample> s;
  const int n = static_cast<int>(std::lround(duration * rate)) + 1;
  for (int k = 0; k < n; ++k) {
    const double t = k / rate;
    ImuSample z;
    z.t = t0 + t;
    z.gyro = Vec3(0.5 * std::sin(1.3 * t + 0.2), -0.4 * std::cos(0.7 * t),
                  0.3 * std::sin(2.1 * t + 1.0)) +
             Vec3(0.01, -0.02, 0.015);
    z.accel = Vec3(1.5 * std::cos(0.9 * t), 2.0 * std::sin(1.7 * t + 0.3),
                   9.81 + 0.8 * std::sin(0.5 * t)) +
              Vec3(0.05, 0.1, -0.08);
    s.push_back(z);
  }
  return s;
}

inline ImuNoise TestNoise() {
  // gyro and accelerometer noise densities, then gyro and accelerometer random walks
  return ImuNoise{2e-3, 3e-2, 4e-4, 6e-3};
}

/// The whole of `s` as one window.
inline SampleWindow WholeWindow(const std::vector<ImuSample>& s) {
  SampleWindow w;
  EXPECT_TRUE(MakeWindow(s.data(), s.size(), s.front().t, s.back().t, w).ok());
  return w;
}

/// 1 s of SmoothImu as one window, a start state x_s (rotated by about 1.3 rad, moving, biased)
/// and gravity.
struct SmoothScenario {
  std::vector<ImuSample> imu = SmoothImu(1.0);
  SampleWindow w = WholeWindow(imu);
  ImuState x_s;
  Vec3 g = Vec3(0, 0, -9.81);
  SmoothScenario() {
    x_s.R = so3::Exp(Vec3(0.3, -1.1, 0.7));
    x_s.p = Vec3(3, -2, 1);
    x_s.v = Vec3(0.5, 1.5, -0.2);
    x_s.bg = Vec3(0.01, -0.02, 0.005);
    x_s.ba = Vec3(0.1, 0.05, -0.2);
  }
};

}  // namespace imuconv::test
