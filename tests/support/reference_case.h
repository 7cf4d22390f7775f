// A reference case of tests/data/reference/cases (the samples, noise and start state GTSAM was
// run on, tests/data/README.md): its JSON document by id, its noise densities, and what GTSAM
// and the other systems (tests/data/reference/anchors) computed on it.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "imuconv/types.h"
#include "imuconv_test.h"

namespace imuconv::test {

inline nlohmann::json CaseJson(const std::string& id) {
  return ReadJson(DataPath("reference/cases/" + id + ".json"));
}

/// GTSAM's outputs for the case (tests/data/reference/gtsam/<id>.gtsam.json): each hold of the
/// samples ("zoh", "mid") and scheme ("manifold", "tangent") under its own key.
inline nlohmann::json GtsamReferenceJson(const std::string& id) {
  return ReadJson(DataPath("reference/gtsam/" + id + ".gtsam.json"));
}

/// Another system's outputs for the case: the anchor file of `system` (its folder under
/// tests/data/reference/anchors: "basalt", "orb-slam3", ...) for the reference case `case_id`.
inline nlohmann::json AnchorJson(const std::string& system, const std::string& case_id) {
  return ReadJson(DataPath("reference/anchors/" + system + "/" + case_id + ".json"));
}

/// The case's "noise": the continuous densities and random walks its samples were drawn with.
inline ImuNoise CaseNoise(const nlohmann::json& c) {
  const nlohmann::json& n = c.at("noise");
  ImuNoise noise;
  noise.gyro_noise_density = n.at("gyro_noise_density").get<double>();
  noise.accel_noise_density = n.at("accel_noise_density").get<double>();
  noise.gyro_random_walk = n.at("gyro_random_walk").get<double>();
  noise.accel_random_walk = n.at("accel_random_walk").get<double>();
  return noise;
}

}  // namespace imuconv::test
