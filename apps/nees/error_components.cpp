// The nine error components' statistics (error_components.h).
#include "error_components.h"

#include <algorithm>
#include <cmath>

#include "split_factors.h"

namespace imuconv::nees {

const char* const kOffsetRule =
    "|mean| > rms / sqrt(2): the mean of the standardized error is larger than its standard "
    "deviation about "
    "the mean";

const std::vector<std::string>& ComponentNames() {
  static const std::vector<std::string> names = {"p.x",     "p.y", "p.z", "theta.x", "theta.y",
                                                 "theta.z", "v.x", "v.y", "v.z"};
  return names;
}

double SignTestPValue(std::size_t k, std::size_t n) {
  if (n == 0) return 1.0;
  const std::size_t m = std::min(k, n - k);
  // P(X <= m) for X ~ Binomial(n, 1/2), summed in log space (n can be 10^6).
  const double log_total = static_cast<double>(n) * std::log(0.5);
  const double lg_n1 = std::lgamma(static_cast<double>(n) + 1.0);
  double tail = 0.0;
  for (std::size_t i = 0; i <= m; ++i)
    tail += std::exp(lg_n1 - std::lgamma(static_cast<double>(i) + 1.0) -
                     std::lgamma(static_cast<double>(n - i) + 1.0) + log_total);
  return std::min(1.0, 2.0 * tail);
}

std::vector<ComponentStatistics> ComponentStatisticsOf(const std::vector<Vec9>& error,
                                                       const std::vector<Mat9>& cov_gyro,
                                                       const std::vector<Mat9>& cov_accel,
                                                       double k_gyro, double k_accel) {
  std::vector<ComponentStatistics> out(9);
  for (int c = 0; c < 9; ++c) {
    ComponentStatistics& s = out[static_cast<std::size_t>(c)];
    s.name = ComponentNames()[static_cast<std::size_t>(c)];
    double sum = 0.0, sum_sq = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < error.size() && i < cov_gyro.size() && i < cov_accel.size(); ++i) {
      const double var = ScaledCovariance(cov_gyro[i], cov_accel[i], k_gyro, k_accel)(c, c);
      const double e = error[i](c);
      if (!(var > 0.0) || !std::isfinite(var) || !std::isfinite(e)) continue;
      const double z = e / std::sqrt(var);
      sum += z;
      sum_sq += z * z;
      ++n;
      s.positive += e > 0.0 ? 1 : 0;
      s.nonzero += e != 0.0 ? 1 : 0;
    }
    if (n == 0) {
      s.mean_standardized = s.rms_standardized = std::nan("");
      continue;
    }
    s.mean_standardized = sum / static_cast<double>(n);
    s.rms_standardized = std::sqrt(sum_sq / static_cast<double>(n));
    s.sign_p_value = SignTestPValue(s.positive, s.nonzero);
    s.offset = std::abs(s.mean_standardized) > s.rms_standardized / std::sqrt(2.0);
  }
  return out;
}

}  // namespace imuconv::nees
