// Order statistics of a sample of NEES values: the median and a percentile. Header-only so the
// test recomputes the report's figures with the same definitions from the values it prints.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace imuconv::nees {

/// The q-quantile, 0 <= q <= 1, of a non-empty sample by linear interpolation between the order
/// statistics at rank h = (n - 1) q (Hyndman and Fan's definition 7, NumPy's default): q = 0.5
/// is the usual median (the mean of the two middle values for even n).
inline double SampleQuantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double h = (static_cast<double>(values.size()) - 1.0) * q;
  const std::size_t below = static_cast<std::size_t>(std::floor(h));
  if (below + 1 >= values.size()) return values.back();
  return values[below] + (h - static_cast<double>(below)) * (values[below + 1] - values[below]);
}

inline double SampleMedian(const std::vector<double>& values) {
  return SampleQuantile(values, 0.5);
}

}  // namespace imuconv::nees
