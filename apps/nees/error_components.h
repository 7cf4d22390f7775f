// Each of the nine error components of imuconv nees on its own, standardized by its sigma under
// the fitted covariance k_g^2 P_g + k_a^2 P_a (split_factors.h): across windows, a component the
// noise explains has mean near 0 and rms near 1. One whose mean dominates its spread is a
// systematic offset that no noise scale can explain (docs/nees.md, "Offsets").
#pragma once

#include <string>
#include <vector>

#include "imuconv/types.h"

namespace imuconv::nees {

struct ComponentStatistics {
  std::string name;                ///< "p.x" ... "v.z"
  double mean_standardized = 0.0;  ///< mean over windows of e_i / sigma_i
  double rms_standardized = 0.0;   ///< sqrt(mean of (e_i / sigma_i)^2)
  std::size_t positive = 0;        ///< windows with e_i > 0
  std::size_t nonzero = 0;         ///< windows with e_i != 0 (the sign test's n)
  /// Two-sided sign test: the probability, if each window's sign were a fair coin, of a split at
  /// least as uneven as positive : nonzero - positive.
  double sign_p_value = 1.0;
  /// The mean dominates the spread: |mean| > rms / sqrt(2), i.e. mean^2 > the variance about the
  /// mean (rms^2 = mean^2 + variance), kOffsetRule.
  bool offset = false;
};

/// The offset rule in words, as the reports state it.
extern const char* const kOffsetRule;

/// The names of the nine components, in the error's order [p, theta, v] x [x, y, z].
const std::vector<std::string>& ComponentNames();

/// Two-sided sign-test p-value of k successes in n fair coin flips: min(1, 2 P(X <= min(k, n-k))).
double SignTestPValue(std::size_t k, std::size_t n);

/// The nine components' statistics over windows, each error standardized by the square root of
/// the diagonal of ScaledCovariance(cov_gyro, cov_accel, k_gyro, k_accel). Components whose sigma
/// is 0 or not finite in a window skip that window.
std::vector<ComponentStatistics> ComponentStatisticsOf(const std::vector<Vec9>& error,
                                                       const std::vector<Mat9>& cov_gyro,
                                                       const std::vector<Mat9>& cov_accel,
                                                       double k_gyro, double k_accel);

}  // namespace imuconv::nees
