// A matrix as JSON rows [[...], ...], the layout of every matrix in imuconv's documents: the
// inverse of JsonMatrix (imuconv_test.h), for tests that write a changed matrix into an input.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace imuconv::test {

inline nlohmann::json JsonRows(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    nlohmann::json r = nlohmann::json::array();
    for (Eigen::Index k = 0; k < m.cols(); ++k) r.push_back(m(i, k));
    rows.push_back(r);
  }
  return rows;
}

}  // namespace imuconv::test
