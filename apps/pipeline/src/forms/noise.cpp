// The noise form, read and written (json_io.h).
#include "imuconv/pipeline/json_io.h"

#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/kalibr_yaml.h"
#include "task_common.h"

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

std::optional<ImuNoise> NoiseFormFromJson(const Node& n, const std::string& base_dir,
                                          std::string* kalibr_file) {
  if (!(n.is_object() && n.has("kalibr"))) return NoiseFromJson(n);
  // {"kalibr": "imu.yaml"}: the file is read now (a few hundred bytes), so that its problems
  // are reported with the document's.
  n.expect_object({"kalibr"});
  const auto f = n.string("kalibr", true);
  if (!f) return std::nullopt;
  const std::string path = ParseContext(n.checker(), base_dir).resolve(*f);
  if (kalibr_file) *kalibr_file = path;
  try {
    return data::ReadKalibrImuYaml(path);
  } catch (const ReadError& e) {
    n.checker().error(n.child_pointer("kalibr"), e.what());
    return std::nullopt;
  }
}

}  // namespace imuconv::pipeline
