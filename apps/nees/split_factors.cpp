// The two noise factors (split_factors.h).
#include "split_factors.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

#include "imuconv/chi_square.h"
#include "order_statistics.h"

namespace imuconv::nees {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The median over windows of the v block's NEES under k_g^2 P_g + k_a^2 P_a.
double MedianVNees(const std::vector<Vec9>& error, const std::vector<Mat9>& cov_gyro,
                   const std::vector<Mat9>& cov_accel, double k_gyro, double k_accel) {
  std::vector<double> nees(error.size());
  for (std::size_t i = 0; i < error.size(); ++i)
    nees[i] = BlockNees(error[i], ScaledCovariance(cov_gyro[i], cov_accel[i], k_gyro, k_accel), 6);
  return SampleMedian(nees);
}

}  // namespace

double ChiSquare3Median() {
  static const double median = ChiSquareQuantileExact(3, 0.5);
  return median;
}

double BlockNees(const Vec9& error, const Mat9& cov, int offset) {
  const Mat3 block =
      0.5 * (cov.block<3, 3>(offset, offset) + cov.block<3, 3>(offset, offset).transpose());
  const Eigen::LLT<Mat3> llt(block);
  if (llt.info() != Eigen::Success)  // Eigen's LLT fails on a pivot <= 0: not positive definite
    return std::numeric_limits<double>::infinity();
  return llt.matrixL().solve(error.segment<3>(offset)).squaredNorm();
}

Mat9 ScaledCovariance(const Mat9& cov_gyro, const Mat9& cov_accel, double k_gyro, double k_accel) {
  return k_gyro * k_gyro * cov_gyro + k_accel * k_accel * cov_accel;
}

double FitGyroFactor(const std::vector<Vec9>& error, const std::vector<Mat9>& cov_gyro) {
  if (error.empty() || error.size() != cov_gyro.size()) return kNaN;
  std::vector<double> nees(error.size());
  for (std::size_t i = 0; i < error.size(); ++i) {
    nees[i] = BlockNees(error[i], cov_gyro[i], 3);
    if (!std::isfinite(nees[i])) return kNaN;
  }
  return std::sqrt(SampleMedian(nees) / ChiSquare3Median());
}

double FitAccelFactor(const std::vector<Vec9>& error, const std::vector<Mat9>& cov_gyro,
                      const std::vector<Mat9>& cov_accel, double k_gyro) {
  if (!std::isfinite(k_gyro) || error.empty() || error.size() != cov_gyro.size() ||
      error.size() != cov_accel.size())
    return kNaN;
  const double target = ChiSquare3Median();
  // f(k) = median v NEES - target decreases in k; bracket its root on a log scale. The ends
  // 1e-12 and 1e12 are far outside any scale a density could be off by.
  double lo = 1.0, hi = 1.0;
  while (MedianVNees(error, cov_gyro, cov_accel, k_gyro, lo) <= target) {
    if (lo < 1e-12) return 0.0;  // the gyro part alone explains the v errors
    lo /= 10.0;
  }
  while (MedianVNees(error, cov_gyro, cov_accel, k_gyro, hi) > target) {
    if (hi > 1e12) return kNaN;  // no accelerometer part to scale
    hi *= 10.0;
  }
  // Bisection on log k until the bracket is 1e-13 relative wide (about 45 halvings of a decade).
  for (int i = 0; i < 200 && hi / lo - 1.0 > 1e-13; ++i) {
    const double mid = std::sqrt(lo * hi);
    (MedianVNees(error, cov_gyro, cov_accel, k_gyro, mid) > target ? lo : hi) = mid;
  }
  return std::sqrt(lo * hi);
}

}  // namespace imuconv::nees
