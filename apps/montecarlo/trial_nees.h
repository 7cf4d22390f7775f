// Each Monte Carlo trial's NEES under the predicted covariance: e_i^T Sigma^-1 e_i, chi-square
// with 15 dof for a consistent method, so the report can show their histogram against the
// chi-square(15) density (the verdict itself uses their mean, statistics.h). Header-only.
#pragma once

#include <Eigen/Cholesky>
#include <vector>

#include "imuconv/types.h"

namespace imuconv::montecarlo {

/// Empty when Sigma is not positive definite (ComputeStatistics refuses that case first).
inline std::vector<double> TrialNees(const std::vector<Vec15>& errors, const Mat15& sigma) {
  const Eigen::LLT<Mat15> llt(sigma);
  if (llt.info() != Eigen::Success) return {};
  std::vector<double> nees;
  nees.reserve(errors.size());
  for (const Vec15& e : errors) nees.push_back(llt.matrixL().solve(e).squaredNorm());
  return nees;
}

}  // namespace imuconv::montecarlo
