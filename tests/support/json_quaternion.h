// A quaternion as the test data write it: a JSON array [w, x, y, z] (the reference cases'
// q_wxyz, the anchors' quaternions).
#pragma once

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

namespace imuconv::test {

/// The quaternion of `q` = [w, x, y, z], as written (not normalized).
inline Eigen::Quaterniond JsonQuaternionWxyz(const nlohmann::json& q) {
  return Eigen::Quaterniond(q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>(),
                            q.at(3).get<double>());
}

}  // namespace imuconv::test
