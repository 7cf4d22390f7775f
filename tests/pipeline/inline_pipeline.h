// Pieces of the small inline pipelines that the pipeline tests write by hand: the noise block,
// samples of constant motion, a one-task pipeline, and start states.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <string>

namespace imuconv::test {

/// A pipeline's "noise" object (schemas/pipeline.schema.json; docs/noise.md): the white-noise
/// densities of the gyroscope and the accelerometer and their bias random walks.
inline nlohmann::json NoiseDensities(double gyro_noise_density, double accel_noise_density,
                                     double gyro_random_walk, double accel_random_walk) {
  return {{"gyro_noise_density", gyro_noise_density},
          {"accel_noise_density", accel_noise_density},
          {"gyro_random_walk", gyro_random_walk},
          {"accel_random_walk", accel_random_walk}};
}

/// A pipeline's "noise": densities of a tactical-grade IMU. The tests that use it check what a
/// pipeline accepts and writes, not the covariances, so any valid densities would do.
inline nlohmann::json TacticalNoiseDensities() { return NoiseDensities(1e-4, 1e-3, 1e-5, 1e-4); }

/// Inline samples k = 0 .. last, one every `step` seconds from t = 0, all with the same
/// [wx, wy, wz, ax, ay, az].
inline nlohmann::json ConstantSamples(int last, double step,
                                      const std::array<double, 6>& gyro_accel) {
  nlohmann::json samples = nlohmann::json::array();
  for (int k = 0; k <= last; ++k) {
    nlohmann::json s = {step * k};
    for (double x : gyro_accel) s.push_back(x);
    samples.push_back(s);
  }
  return samples;
}

/// The [wx, wy, wz, ax, ay, az] of the small pipelines' constant motion: turning about all
/// three axes, accelerating, gravity along z.
constexpr std::array<double, 6> kConstantMotion = {0.1, -0.2, 0.3, 0.5, 0.1, 9.8};

/// A pipeline of 0.1 s of inline samples of constant motion at 100 Hz, with the tactical
/// densities, running `tasks` (the tests give it their own).
inline nlohmann::json TenthSecondAt100HzRunning(const nlohmann::json& tasks) {
  return {{"noise", TacticalNoiseDensities()},
          {"imu", {{"format", "inline"}, {"samples", ConstantSamples(10, 0.01, kConstantMotion)}}},
          {"tasks", tasks}};
}

/// A `propagate` task named `name`: rk4 from `state` over [0, 0.1] s.
inline nlohmann::json Rk4PropagationOverTenthSecond(const std::string& name,
                                                    const nlohmann::json& state) {
  return {{"type", "propagate"},
          {"name", name},
          {"propagator", "rk4"},
          {"start", {{"state", state}}},
          {"interval", {{"t_start", 0.0}, {"t_end", 0.1}}}};
}

/// A `preintegrate` task named `name`: measurements by rk4 propagation between the `keyframes`
/// (a list of times, or {start, end, step}).
inline nlohmann::json Rk4PreintegrationAt(const std::string& name,
                                          const nlohmann::json& keyframes) {
  return {{"type", "preintegrate"},
          {"name", name},
          {"method", {{"propagator", "rk4"}}},
          {"keyframes", keyframes}};
}

/// A pipeline of 0.1 s of inline samples at 200 Hz and one `manifold` preintegration over it
/// (keyframes 0 and 0.1 s), whose covariance depends on every density of `noise`.
inline nlohmann::json OnePreintegrationWithNoise(const nlohmann::json& noise) {
  return {{"noise", noise},
          {"imu", {{"format", "inline"}, {"samples", ConstantSamples(20, 0.005, kConstantMotion)}}},
          {"tasks",
           {{{"type", "preintegrate"},
             {"name", "pre"},
             {"method", {{"preintegrator", "manifold"}}},
             {"keyframes", {0.0, 0.1}}}}}};
}

/// A start state at the origin, unrotated, moving at 1 m/s along x.
inline nlohmann::json UnitSpeedStartState() {
  return {{"p", {0, 0, 0}}, {"q_wxyz", {1, 0, 0, 0}}, {"v", {1, 0, 0}}};
}

/// A start state at rest at the origin, unrotated, with zero biases (all five stated).
inline nlohmann::json RestAtOriginWithZeroBiases() {
  return {{"p", {0, 0, 0}},
          {"q_wxyz", {1, 0, 0, 0}},
          {"v", {0, 0, 0}},
          {"bg", {0, 0, 0}},
          {"ba", {0, 0, 0}}};
}

}  // namespace imuconv::test
