// The chi-square distribution, exactly (to double precision), for the NEES of one window: a
// 9-dim error under its own covariance is chi-square with 9 dof, and the bounds and the median
// the report quotes are its quantiles. apps/montecarlo/statistics.h has the Wilson-Hilferty
// approximation, good to 1e-3 for dof >= 30 only; at 9 dof its tails are off by more than the
// three digits the tables give, so here the CDF is the regularized lower incomplete gamma
// function P(dof/2, x/2), inverted by bisection.
#pragma once

#include <cmath>
#include <limits>

namespace imuconv::nees {

/// P(a, x) = gamma(a, x) / Gamma(a), the regularized lower incomplete gamma function, a > 0,
/// x >= 0: the series sum x^n / ((a+1)...(a+n)) for x < a + 1, else the continued fraction for
/// Q = 1 - P by Lentz's method (both converge fast there; Numerical Recipes, section 6.2).
inline double RegularizedLowerGamma(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefactor = a * std::log(x) - x - std::lgamma(a);
  constexpr double eps = 1e-16;
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 1000 && std::abs(term) > eps * std::abs(sum); ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return sum * std::exp(log_prefactor);
  }
  constexpr double tiny = std::numeric_limits<double>::min() / eps;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < eps) break;
  }
  return 1.0 - std::exp(log_prefactor) * h;
}

/// The chi-square CDF with `dof` degrees of freedom.
inline double ChiSquareCdf(double dof, double x) { return RegularizedLowerGamma(dof / 2.0, x / 2.0); }

/// The chi-square quantile: the x with ChiSquareCdf(dof, x) = p, 0 < p < 1, by bisection on
/// the monotone CDF until the bracket is one ulp wide.
inline double ChiSquareQuantile(double dof, double p) {
  double lo = 0.0, hi = dof + 10.0 * std::sqrt(2.0 * dof) + 10.0;
  while (ChiSquareCdf(dof, hi) < p) hi *= 2.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (ChiSquareCdf(dof, mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace imuconv::nees
