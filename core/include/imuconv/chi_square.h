// The chi-square distribution to double precision, for every judgment that quotes it: the NEES
// of one nees window (9 dof; the theta block's 3), a Monte Carlo run's NEES sum of N trials
// (15 N dof, up to 1.5e8 at the 10^7 trials allowed) and its KL statistic (135). The CDF is the
// regularized incomplete gamma function P(dof/2, x/2), by its power series below a + 1 and by
// the continued fraction of Q = 1 - P above (Lentz's method). Near x = a both need about
// sqrt(a) terms, not a fixed count: the series' terms shrink like exp(-n^2 / (2a)), so
// 12 sqrt(a) + 100 terms reach 1e-16 (exp(-72) ~ 5e-32) at any a; the continued fraction
// converges no slower there. The prefactor x^a e^-x / Gamma(a) is formed in logs; its exponent,
// ~a ln a, is summed to ~1e-16 relative, so at a = 7.5e7 it carries ~2e-7 of relative error into
// p, far below the 0.5 % levels it is compared with.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace imuconv {

/// P(a, x) and Q(a, x) = 1 - P(a, x), each computed directly where it is the small one, so
/// that a tail probability of 1e-300 is not lost in 1 - (1 - 1e-300).
struct GammaTails {
  double lower = 0.0, upper = 1.0;
};

inline GammaTails RegularizedGamma(double a, double x) {
  if (!(x > 0.0)) return {0.0, 1.0};
  if (std::isinf(x)) return {1.0, 0.0};
  const double log_prefactor = a * std::log(x) - x - std::lgamma(a);
  constexpr double eps = 1e-17;
  const int max_terms = static_cast<int>(12.0 * std::sqrt(a) + 100.0);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < max_terms && term > eps * sum; ++n) {
      term *= x / (a + n);
      sum += term;
    }
    const double lower = std::exp(log_prefactor + std::log(sum));
    return {lower, 1.0 - lower};
  }
  constexpr double tiny = std::numeric_limits<double>::min() / eps;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < max_terms; ++i) {
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
  const double upper = std::exp(log_prefactor + std::log(h));
  return {1.0 - upper, upper};
}

/// Pr(X <= x) and Pr(X > x) for X chi-square with `dof` degrees of freedom.
inline GammaTails ChiSquareTails(double dof, double x) {
  return RegularizedGamma(dof / 2.0, x / 2.0);
}

/// The chi-square CDF Pr(X <= x).
inline double ChiSquareCdf(double dof, double x) { return ChiSquareTails(dof, x).lower; }

/// The x with Pr(X <= x) = p (0 < p < 1), by bisection on the monotone CDF until the bracket is
/// one ulp wide (the lower tail compared for p <= 1/2, the upper one above: both exact).
inline double ChiSquareQuantileExact(double dof, double p) {
  auto below = [&](double x) {
    const GammaTails t = ChiSquareTails(dof, x);
    return p <= 0.5 ? t.lower < p : t.upper > 1.0 - p;
  };
  double lo = 0.0, hi = dof + 10.0 * std::sqrt(2.0 * dof) + 10.0;
  while (below(hi)) hi *= 2.0;
  for (int i = 0; i < 2100; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (below(mid) ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace imuconv
