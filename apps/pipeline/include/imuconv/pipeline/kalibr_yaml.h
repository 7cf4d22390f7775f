// Noise from a Kalibr IMU file (the imu.yaml that Kalibr's camera-IMU calibration reads):
//   accelerometer_noise_density  m/s^2/sqrt(Hz)   continuous-time white noise density
//   accelerometer_random_walk    m/s^3/sqrt(Hz)   continuous-time bias random walk density
//   gyroscope_noise_density      rad/s/sqrt(Hz)
//   gyroscope_random_walk        rad/s^2/sqrt(Hz)
//   update_rate                  Hz (optional here; checked if present)
// These are the four continuous densities imuconv's "noise" takes, unit for unit, so they are
// copied, not converted. Other keys (rostopic, and T_i_b, model, time_offset in the files
// Kalibr writes back) are someone else's and are passed over. Kalibr's result files nest the
// keys under imu0 (imu1, ...): a file with exactly one such entry is read too.
#pragma once

#include <string>

#include "imuconv/types.h"

namespace imuconv::pipeline::data {

/// Largest imu.yaml read: 64 KiB (a real one is a few hundred bytes).
inline constexpr std::size_t kMaxKalibrYamlBytes = std::size_t{64} << 10;

/// Throws ReadError naming the file and the line of the problem (0 for the whole file).
ImuNoise ReadKalibrImuYaml(const std::string& path);

}  // namespace imuconv::pipeline::data
