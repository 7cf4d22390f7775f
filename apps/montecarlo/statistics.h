// The statistics of a Monte Carlo covariance check, header-only so that tests can use them
// directly: N end errors e_i (15-vectors) against a predicted covariance Sigma = L L^T.
//
// Whitened, y_i = L^-1 e_i is N(0, I) when Sigma is right. From it:
//   - NEES_i = |y_i|^2, chi-square with 15 dof; the sum over N independent trials is
//     chi-square with 15 N dof, so the NEES mean has the two-sided bounds
//     [chi2_{15N}(a/2), chi2_{15N}(1 - a/2)] / N (Bar-Shalom's consistency test);
//   - the KL divergence of the fitted Gaussian N(mean, S_ml) (S_ml the maximum-likelihood,
//     1/N, covariance about the sample mean) from the predicted N(0, Sigma):
//       KL = (tr W + |m|^2 - 15 - ln det W) / 2,  W = L^-1 S_ml L^-T, m = L^-1 mean.
//     2 N KL is the likelihood-ratio statistic of H0 {mean 0, covariance Sigma} against any
//     Gaussian, asymptotically chi-square with 15 + 15*16/2 = 135 dof; with Bartlett's
//     correction rho = 1 - (2k^2 + 3k - 1) / (6 (N-1) (k+1)) of its covariance part (Anderson,
//     An Introduction to Multivariate Statistical Analysis, 3rd ed., section 10.8), so
//     KL <= chi2_135(q) / (2 N rho) holds with probability q under H0. At N = 1000, q = 0.99
//     that is 0.088, next to the 0.08 Basalt's own test asks for at N = 1000;
//   - the relative Frobenius error |S - Sigma|_F / |Sigma|_F of the unbiased sample covariance
//     (GTSAM's measure; dominated by the largest block, so reported, not judged).
// tests/preintegrators/whitened.h and tests/integrators/monte_carlo.cpp whiten the same way
// (second moment of y, trace = NEES mean).
#pragma once

#include <Eigen/Cholesky>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "imuconv/types.h"

namespace imuconv::montecarlo {

/// Standard normal quantile (Acklam's rational approximation, relative error below 1.2e-9,
/// then one Newton step with erfc): enough for confidence bounds.
inline double NormalQuantile(double p) {
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                                 1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                 6.680131188771972e+01, -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                 -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                 3.754408661907416e+00};
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
/// approximation: for dof >= 30 its relative error is below 1e-3 in the tails used here
/// (against the tables: chi2_30(0.975) = 46.979, chi2_120(0.99) = 158.950), and it improves
/// with dof; the bounds here have 15 N >= 240 and 135 dof.
inline double ChiSquareQuantile(double dof, double p) {
  const double h = 2.0 / (9.0 * dof);
  const double t = 1.0 - h + NormalQuantile(p) * std::sqrt(h);
  return dof * t * t * t;
}

constexpr int kDim = 15;
/// Two-sided confidence of the NEES bounds, and the one-sided level of the KL bound.
constexpr double kNeesConfidence = 0.95;
constexpr double kKlLevel = 0.99;

struct Statistics {
  int trials = 0;
  Vec15 mean = Vec15::Zero();
  Mat15 sample_cov = Mat15::Zero();  ///< unbiased, 1/(N-1), about the sample mean
  double relative_frobenius = 0.0;
  double nees_mean = 0.0;
  std::array<double, 2> nees_bounds{};  ///< kNeesConfidence two-sided, for the NEES mean
  double kl = 0.0;
  double kl_bound = 0.0;  ///< kKlLevel quantile of KL under H0
};

/// NEES-mean bounds for N trials of 15-dim errors.
inline std::array<double, 2> NeesBounds(int trials) {
  const double dof = kDim * static_cast<double>(trials), alpha = 1.0 - kNeesConfidence;
  return {ChiSquareQuantile(dof, alpha / 2) / trials, ChiSquareQuantile(dof, 1 - alpha / 2) / trials};
}

/// Upper kKlLevel bound of the KL divergence for N trials (see the file comment).
inline double KlBound(int trials) {
  const double k = kDim, n = trials;
  const double rho = 1.0 - (2 * k * k + 3 * k - 1) / (6 * (n - 1) * (k + 1));
  return ChiSquareQuantile(k + k * (k + 1) / 2, kKlLevel) / (2 * n * rho);
}

/// The statistics of `errors` (at least 16, so that S is full rank) against `Sigma`, which
/// must be positive definite (`ok` false otherwise). The sums run in the order of `errors`.
inline bool ComputeStatistics(const std::vector<Vec15>& errors, const Mat15& Sigma, Statistics& st) {
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
  return true;
}

}  // namespace imuconv::montecarlo
