// The statistics of a Monte Carlo covariance check, header-only so that tests can use them
// directly: N end errors e_i (15-vectors) against a predicted covariance Sigma = L L^T.
//
// Whitened, y_i = L^-1 e_i is N(0, I) when Sigma is right. From it two tests, each with an
// exact or corrected null distribution and a p-value (docs/montecarlo.md, "The verdict"):
//   - NEES_i = |y_i|^2 is chi-square with 15 dof; the sum over N independent trials is
//     chi-square with 15 N dof exactly, so nees_p_value is the two-sided tail of N * nees_mean
//     in chi-square(15 N) (Bar-Shalom's consistency test), and the NEES-mean bounds are its
//     quantiles at kTestLevel / 2 and 1 - kTestLevel / 2, divided by N;
//   - the KL divergence of the fitted Gaussian N(mean, S_ml) (S_ml the maximum-likelihood,
//     1/N, covariance about the sample mean) from the predicted N(0, Sigma):
//       KL = (tr W + |m|^2 - 15 - ln det W) / 2,  W = L^-1 S_ml L^-T, m = L^-1 mean.
//     2 N KL is exactly -2 ln(lambda) of the likelihood-ratio test of H0 {mean 0, covariance
//     Sigma} against any Gaussian (Anderson, An Introduction to Multivariate Statistical
//     Analysis, 3rd ed., section 10.9, the test that a mean vector and a covariance matrix are
//     both given ones). Asymptotically it is chi-square with p(p+3)/2 = 135 dof (p = 15); with
//     Bartlett's correction for this joint hypothesis,
//       rho = 1 - (2 p^2 + 9 p + 11) / (6 N (p + 3)),
//     2 N rho KL is chi-square(135) up to O(N^-2). kl_p_value is its upper tail. The
//     correction matters at small N (rho = 0.89 at N = 50) and is checked by simulation at
//     N = 20 to 1000 in tests/montecarlo/verdict_rate.cpp;
//   - the relative Frobenius error |S - Sigma|_F / |Sigma|_F of the unbiased sample covariance
//     (GTSAM's measure; dominated by the largest block, so reported, not judged).
// The verdict (montecarlo.cpp, Conclude) is "inconsistent" when either p-value is below
// kTestLevel = kFalseAlarmRate / 2: by Bonferroni's inequality Pr(reject) <= Pr(p_nees <
// a/2) + Pr(p_kl < a/2) = a whatever the dependence between the two statistics (they are
// dependent: both contain tr W), so a correct covariance is called inconsistent at most
// kFalseAlarmRate = 1 % of the time. Holm's step-down gives the same global verdict for two
// tests (it rejects the intersection exactly when min p < a/2), and Fisher's combination
// assumes independence, which does not hold here; so Bonferroni.
// tests/preintegrators/whitened.h and tests/integrators/monte_carlo.cpp whiten the same way
// (second moment of y, trace = NEES mean).
#pragma once

#include <Eigen/Cholesky>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "imuconv/chi_square.h"
#include "imuconv/types.h"

namespace imuconv::montecarlo {

/// Standard normal quantile (Acklam's rational approximation, relative error below 1.2e-9,
/// then one Newton step with erfc): enough for confidence bounds.
inline double NormalQuantile(double p) {
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                 -2.759285104469687e+02, 1.383577518672690e+02,
                                 -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                 -1.556989798598866e+02, 6.680131188771972e+01,
                                 -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                 -2.400758277161838e+00, -2.549732539343734e+00,
                                 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                 2.445134137142996e+00, 3.754408661907416e+00};
  const double plow = 0.02425;
  double x;
  if (p < plow) {
    const double q = std::sqrt(-2 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else if (p <= 1 - plow) {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  } else {
    const double q = std::sqrt(-2 * std::log(1 - p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  // Newton (Halley) refinement against the exact CDF 0.5 erfc(-x / sqrt 2).
  const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - p;
  const double u = e * std::sqrt(2 * M_PI) * std::exp(x * x / 2);
  return x - u / (1 + x * u / 2);
}

/// Chi-square quantile with `dof` degrees of freedom, by the Wilson-Hilferty cube-root
/// approximation: for dof >= 30 its relative error is below 1e-3 in the tails (against the
/// tables: chi2_30(0.975) = 46.979, chi2_120(0.99) = 158.950). A quick closed form for the
/// tests' histogram bounds; the verdict's bounds and p-values use imuconv/chi_square.h, exactly.
inline double ChiSquareQuantile(double dof, double p) {
  const double h = 2.0 / (9.0 * dof);
  const double t = 1.0 - h + NormalQuantile(p) * std::sqrt(h);
  return dof * t * t * t;
}

constexpr int kDim = 15;
/// The design false-alarm rate of the verdict: the probability that a correct covariance is
/// called inconsistent is at most this (Bonferroni over the two tests, see the file comment).
constexpr double kFalseAlarmRate = 0.01;
/// The level of each of the two tests.
constexpr double kTestLevel = kFalseAlarmRate / 2;
/// Two-sided confidence of the NEES bounds, and the one-sided level of the KL bound: each
/// test's acceptance region, 1 - kTestLevel.
constexpr double kNeesConfidence = 1.0 - kTestLevel;
constexpr double kKlLevel = 1.0 - kTestLevel;
/// From this many trials on, the corrected chi-square(135) is the KL statistic's null
/// distribution to within the simulation's resolution: the rate of kl_p_value < 0.5 % on
/// exact Gaussian errors measured 0.50 % and 0.57 % at N = 200 (4000 and 10 000 replicas,
/// standard error 0.07 %), 0.53 % at N = 1000 (15 000), but 0.70 % at N = 50 and 5.4 % at N = 20,
/// where the O(N^-2) terms Bartlett's factor leaves are not small (15 dimensions from 20 draws).
/// Below it the output says that the rate is not held.
constexpr int kKlChiSquareFromTrials = 200;
/// Degrees of freedom of the KL likelihood-ratio statistic: 15 for the mean, 120 for the
/// covariance.
constexpr int kKlDof = kDim * (kDim + 3) / 2;

struct Statistics {
  int trials = 0;
  Vec15 mean = Vec15::Zero();
  Mat15 sample_cov = Mat15::Zero();  ///< unbiased, 1/(N-1), about the sample mean
  double relative_frobenius = 0.0;
  double nees_mean = 0.0;
  std::array<double, 2> nees_bounds{};  ///< kNeesConfidence two-sided, for the NEES mean
  double nees_p_value = 1.0;            ///< two-sided, of N * nees_mean in chi-square(15 N)
  double kl = 0.0;
  double kl_bound = 0.0;    ///< kKlLevel quantile of KL under H0
  double kl_p_value = 1.0;  ///< upper tail of 2 N rho KL in chi-square(135)
};

/// NEES-mean bounds for N trials of 15-dim errors: the chi-square(15 N) quantiles at
/// kTestLevel / 2 and 1 - kTestLevel / 2, divided by N.
inline std::array<double, 2> NeesBounds(int trials) {
  const double dof = kDim * static_cast<double>(trials), alpha = 1.0 - kNeesConfidence;
  return {ChiSquareQuantileExact(dof, alpha / 2) / trials,
          ChiSquareQuantileExact(dof, 1 - alpha / 2) / trials};
}

/// The two-sided p-value of a NEES mean over N trials: 2 min(Pr(X <= N m), Pr(X >= N m)),
/// X chi-square(15 N), at most 1.
inline double NeesPValue(int trials, double nees_mean) {
  const GammaTails t = ChiSquareTails(kDim * static_cast<double>(trials), trials * nees_mean);
  return std::min(1.0, 2.0 * std::min(t.lower, t.upper));
}

/// Bartlett's factor rho of the joint mean-and-covariance likelihood-ratio test (file comment).
inline double KlBartlettFactor(int trials) {
  const double p = kDim;
  return 1.0 - (2 * p * p + 9 * p + 11) / (6.0 * trials * (p + 3));
}

/// Upper kKlLevel bound of the KL divergence for N trials (see the file comment).
inline double KlBound(int trials) {
  return ChiSquareQuantileExact(kKlDof, kKlLevel) / (2.0 * trials * KlBartlettFactor(trials));
}

/// The p-value of a KL divergence over N trials: Pr(X >= 2 N rho KL), X chi-square(135).
inline double KlPValue(int trials, double kl) {
  if (std::isinf(kl)) return 0.0;
  return ChiSquareTails(kKlDof, 2.0 * trials * KlBartlettFactor(trials) * kl).upper;
}

/// The statistics of `errors` (at least 16, so that S is full rank) against `Sigma`, which
/// must be positive definite (`ok` false otherwise). The sums run in the order of `errors`.
inline bool ComputeStatistics(const std::vector<Vec15>& errors, const Mat15& Sigma,
                              Statistics& st) {
  const Eigen::LLT<Mat15> llt(Sigma);
  if (llt.info() != Eigen::Success || errors.size() < kDim + 1) return false;
  const int n = static_cast<int>(errors.size());
  st = Statistics{};
  st.trials = n;
  for (const Vec15& e : errors) st.mean += e;
  st.mean /= n;
  Mat15 scatter = Mat15::Zero();
  double nees_sum = 0.0;
  for (const Vec15& e : errors) {
    const Vec15 c = e - st.mean;
    scatter.noalias() += c * c.transpose();
    nees_sum += llt.matrixL().solve(e).squaredNorm();
  }
  st.sample_cov = scatter / (n - 1);
  st.relative_frobenius = (st.sample_cov - Sigma).norm() / Sigma.norm();
  st.nees_mean = nees_sum / n;
  st.nees_bounds = NeesBounds(n);
  st.nees_p_value = NeesPValue(n, st.nees_mean);
  // W = L^-1 S_ml L^-T, m = L^-1 mean.
  Mat15 W = llt.matrixL().solve(Mat15(scatter / n));
  W = llt.matrixL().solve(Mat15(W.transpose()));
  W = 0.5 * (W + W.transpose());
  const Vec15 m = llt.matrixL().solve(st.mean);
  const Eigen::LLT<Mat15> w_llt(W);
  if (w_llt.info() != Eigen::Success) {
    st.kl = std::numeric_limits<double>::infinity();
  } else {
    const double log_det_W = 2.0 * w_llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
    st.kl = 0.5 * (W.trace() + m.squaredNorm() - kDim - log_det_W);
  }
  st.kl_bound = KlBound(n);
  st.kl_p_value = KlPValue(n, st.kl);
  return true;
}

}  // namespace imuconv::montecarlo
