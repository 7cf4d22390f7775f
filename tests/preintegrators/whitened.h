// The Monte Carlo check of a covariance shared by the preintegrator tests: N noisy runs'
// errors whitened by the predicted covariance Sigma = L L^T, W = L^-1 (1/N sum e e^T) L^-T,
// must give I. For N Gaussian runs W's diagonal entries have standard deviation sqrt(2/N),
// its off-diagonal ones 1/sqrt(N), and the NEES mean trace(W) sqrt(30/N).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <vector>

#include "imuconv/types.h"

namespace imuconv::test {

constexpr int kRuns = 4000;
// 5 standard deviations: with ~120 distinct entries the chance that a correct covariance
// fails is ~1e-4 (and the seed is fixed).
inline const double kDiagTol = 5.0 * std::sqrt(2.0 / kRuns);   // 0.112
inline const double kOffTol = 5.0 * std::sqrt(1.0 / kRuns);    // 0.079
inline const double kNeesTol = 5.0 * std::sqrt(30.0 / kRuns);  // 0.433, for 15 dimensions

struct Whitened {
  double diag = 0.0, off = 0.0, nees = 0.0;
};

template <int N>
Whitened WhitenedStats(const Eigen::Matrix<double, N, N>& Sigma,
                       const std::vector<Eigen::Matrix<double, N, 1>>& errors) {
  const Eigen::LLT<Eigen::Matrix<double, N, N>> llt(Sigma);
  EXPECT_EQ(llt.info(), Eigen::Success);
  Eigen::Matrix<double, N, N> W = Eigen::Matrix<double, N, N>::Zero();
  for (const auto& e : errors) {
    const Eigen::Matrix<double, N, 1> z = llt.matrixL().solve(e);
    W.noalias() += z * z.transpose();
  }
  W /= static_cast<double>(errors.size());
  Whitened w;
  w.nees = W.trace();
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j)
      if (i == j)
        w.diag = std::max(w.diag, std::abs(W(i, i) - 1.0));
      else
        w.off = std::max(w.off, std::abs(W(i, j)));
  return w;
}

}  // namespace imuconv::test
