// S with S^T S = C^-1 for a covariance C: S = L^-1 with C = L L^T its lower Cholesky factor, so
// that a whitened residual S r has the identity as covariance (S is lower triangular). Every
// cost of imuconv::ceres whitens this way: the preintegration factor, the state prior and a
// native factor weighted by its measurement's covariance; each says in its own words what
// failed.
#pragma once

#include <Eigen/Cholesky>

namespace imuconv::ceres_factors::detail {

enum class SqrtInformationStatus {
  kOk,
  kNotPositiveDefinite,  ///< C is not finite, or its Cholesky factorization fails
  kNearSingular,         ///< C factors, but L^-1 overflows
};

/// Writes S = L^-1 (C = L L^T) into `S` when the status is kOk.
template <class Matrix>
SqrtInformationStatus InverseCholeskyFactor(const Matrix& C, Matrix& S) {
  if (!C.allFinite()) return SqrtInformationStatus::kNotPositiveDefinite;
  const Eigen::LLT<Matrix> llt(C);
  if (llt.info() != Eigen::Success) return SqrtInformationStatus::kNotPositiveDefinite;
  S = llt.matrixL().solve(Matrix::Identity(C.rows(), C.cols()));
  return S.allFinite() ? SqrtInformationStatus::kOk : SqrtInformationStatus::kNearSingular;
}

}  // namespace imuconv::ceres_factors::detail
