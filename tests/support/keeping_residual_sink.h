// A ResidualSink for tests that read back what a residual plugin wrote: every vector and matrix
// by its path ("raw/residual"), and the squared Mahalanobis distance it reports.
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "imuconv/residual_factor.h"

namespace imuconv::test {

class KeepingResidualSink final : public ResidualSink {
 public:
  std::map<std::string, Eigen::MatrixXd> values;
  double mahalanobis = -1.0;  ///< -1 until the plugin reports one
  void begin_group(const char* name) noexcept override { prefix_.push_back(name); }
  void end_group() noexcept override { prefix_.pop_back(); }
  void vector(const char* name, const double* v, int n) noexcept override {
    values[path(name)] = Eigen::Map<const Eigen::VectorXd>(v, n);
  }
  void matrix(const char* name, const double* m, int rows, int cols) noexcept override {
    values[path(name)] =
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            m, rows, cols);
  }
  void mahalanobis_squared(double d) noexcept override { mahalanobis = d; }

 private:
  std::string path(const char* name) const {
    std::string p;
    for (const auto& g : prefix_) p += g + "/";
    return p + name;
  }
  std::vector<std::string> prefix_;
};

}  // namespace imuconv::test
