// Scale-aware differences for comparing against an independent reference (GTSAM's numbers).
//
// The note's entrywise metric (J. Huai, "IMU Propagation as Preintegration") judges every entry
// below 1e-4 by its absolute error. In a preintegration covariance the bias blocks are ~1e-10
// and their cross terms smaller still, so with a 1e-8 bound they are not checked at all: a sign
// flip of a whole bias block passes. These two metrics judge every entry on its own scale:
//  - a covariance on the correlation scale, |C_ij - E_ij| / sqrt(C_ii C_jj): a correlation
//    error, the same for a 1e-10 bias variance and a 1e2 position variance;
//  - any other matrix relative to the larger of |r_ij| and 1e-4 of its largest entry: entries
//    that are differences of large terms (and so carry those terms' rounding) are judged on
//    the matrix's scale, all others relatively.
// A non-finite estimate is an infinite difference, so NaN never passes.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

namespace imuconv::test {

/// Where the worst entry of a scale-aware comparison is, and how far off it is.
struct ScaledDiff {
  double d = 0.0;
  int row = 0, col = 0;
};

namespace scale_aware_detail {
inline void Keep(ScaledDiff& worst, double d, Eigen::Index i, Eigen::Index j) {
  if (!(d <= worst.d)) {  // also takes NaN and infinity
    worst.d = std::isnan(d) ? std::numeric_limits<double>::infinity() : d;
    worst.row = static_cast<int>(i);
    worst.col = static_cast<int>(j);
  }
}
}  // namespace scale_aware_detail

/// max_ij |ref_ij - est_ij| / sqrt(ref_ii ref_jj) for a covariance `ref`. A zero variance in
/// the reference (a state no noise reaches) has no scale of its own; its row and column are
/// then judged against the largest variance, so an estimate that is not zero there fails too.
template <typename A, typename B>
ScaledDiff CorrelationScaleDiff(const Eigen::MatrixBase<A>& ref, const Eigen::MatrixBase<B>& est) {
  ScaledDiff worst;
  const double largest = ref.diagonal().cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j) {
      double scale = std::sqrt(std::abs(ref(i, i) * ref(j, j)));
      if (!(scale > 0.0)) scale = largest;
      const double e = est(i, j);
      const double d = std::isfinite(e) ? std::abs(ref(i, j) - e) / scale
                                        : std::numeric_limits<double>::infinity();
      scale_aware_detail::Keep(worst, d, i, j);
    }
  return worst;
}

/// max_ij |ref_ij - est_ij| / max(|ref_ij|, floor * max|ref|), floor = 1e-4 unless given.
template <typename A, typename B>
ScaledDiff RelativeAboveFloorDiff(const Eigen::MatrixBase<A>& ref, const Eigen::MatrixBase<B>& est,
                                  double floor = 1e-4) {
  ScaledDiff worst;
  const double small = floor * ref.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j) {
      const double e = est(i, j);
      const double scale = std::max(std::abs(ref(i, j)), small);
      const double d = !std::isfinite(e) ? std::numeric_limits<double>::infinity()
                       : scale > 0.0     ? std::abs(ref(i, j) - e) / scale
                       : ref(i, j) == e  ? 0.0
                                         : std::numeric_limits<double>::infinity();
      scale_aware_detail::Keep(worst, d, i, j);
    }
  return worst;
}

/// |ref_b - est_b|_F / |ref_b|_F for the 3x3 block at block row i, block column j. A zero
/// block of the reference (d theta / d ba, say) has no scale: 0 if the estimate's is zero too,
/// infinity if not.
template <typename A, typename B>
double BlockRelativeDiff(const Eigen::MatrixBase<A>& ref, const Eigen::MatrixBase<B>& est, int i,
                         int j) {
  const double diff =
      (ref.template block<3, 3>(3 * i, 3 * j) - est.template block<3, 3>(3 * i, 3 * j)).norm();
  const double scale = ref.template block<3, 3>(3 * i, 3 * j).norm();
  if (scale > 0.0) return diff / scale;
  return diff == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
}

/// The worst 3x3 block by BlockRelativeDiff; row and col are block indices.
template <typename A, typename B>
ScaledDiff WorstBlockRelativeDiff(const Eigen::MatrixBase<A>& ref,
                                  const Eigen::MatrixBase<B>& est) {
  ScaledDiff worst;
  for (Eigen::Index i = 0; i < ref.rows() / 3; ++i)
    for (Eigen::Index j = 0; j < ref.cols() / 3; ++j)
      scale_aware_detail::Keep(
          worst, BlockRelativeDiff(ref, est, static_cast<int>(i), static_cast<int>(j)), i, j);
  return worst;
}

}  // namespace imuconv::test
