// A matrix as JSON rows, [[m00, m01, ...], [m10, ...], ...]: how every matrix of imuconv's
// outputs is written. Header-only, so that a library that links only the pipeline's timing rules
// (refcase; the aarch64 build's library subset, apps/CMakeLists.txt) writes its matrices the same
// way without the pipeline's forms.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace imuconv::pipeline {

inline nlohmann::json MatrixToJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    nlohmann::json r = nlohmann::json::array();
    for (Eigen::Index k = 0; k < m.cols(); ++k) r.push_back(m(i, k));
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace imuconv::pipeline
