// The noise form, read and written (json_io.h).
#include "imuconv/pipeline/json_io.h"

namespace imuconv::pipeline {

json NoiseToJson(const ImuNoise& n) {
  return {{"gyro_noise_density", n.gyro_noise_density},
          {"accel_noise_density", n.accel_noise_density},
          {"gyro_random_walk", n.gyro_random_walk},
          {"accel_random_walk", n.accel_random_walk}};
}

std::optional<ImuNoise> NoiseFromJson(const Node& n) {
  if (!n.expect_object(
          {"gyro_noise_density", "accel_noise_density", "gyro_random_walk", "accel_random_walk"}))
    return std::nullopt;
  const std::size_t before = n.checker().count();
  ImuNoise q;
  const auto read = [&](const char* key, double& out) {
    if (auto v = n.number(key, true)) {
      if (*v < 0.0)
        n.checker().error(n.child_pointer(key), "expected a non-negative number");
      else
        out = *v;
    }
  };
  read("gyro_noise_density", q.gyro_noise_density);
  read("accel_noise_density", q.accel_noise_density);
  read("gyro_random_walk", q.gyro_random_walk);
  read("accel_random_walk", q.accel_random_walk);
  if (n.checker().count() != before) return std::nullopt;
  return q;
}

}  // namespace imuconv::pipeline
