// Shared helpers for the test suite: a registry with the built plugins, deterministic
// random states, the paper's entrywise difference metric and JSON matrix readers.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cstdio>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "imuconv/registry.h"
#include "imuconv/so3.h"

namespace imuconv::test {

/// One registry per test binary, loaded from the build tree's plugin directory only
/// (IMUCONV_PLUGIN_PATH is not consulted so a user's environment cannot change results).
inline Registry& Plugins() {
  static Registry* reg = [] {
    auto* r = new Registry();
    const auto issues = r->load_directory(Registry::default_plugin_dir());
    for (const auto& i : issues)
      ADD_FAILURE() << "plugin failed to load: " << i.file << ": " << i.message;
    return r;
  }();
  return *reg;
}

inline std::mt19937& Rng() {
  static std::mt19937 rng(20261121);
  return rng;
}

inline Vec3 RandVec(double scale) {
  std::normal_distribution<double> n(0.0, scale);
  return Vec3(n(Rng()), n(Rng()), n(Rng()));
}

inline Vec15 RandVec15(double scale) {
  std::normal_distribution<double> n(0.0, scale);
  Vec15 d;
  for (int i = 0; i < 15; ++i) d[i] = n(Rng());
  return d;
}

/// Identity, tiny and random states: the three cases every Jacobian test runs on.
inline std::vector<ImuState> TestStates() {
  std::vector<ImuState> xs(3);
  xs[1].R = so3::Exp(Vec3(1e-8, 2e-8, -1e-8));
  xs[1].p = Vec3(1e-7, -1e-7, 2e-7);
  xs[1].v = Vec3(2e-7, 1e-7, -1e-7);
  xs[2].R = so3::Exp(RandVec(1.2));
  xs[2].p = RandVec(10.0);
  xs[2].v = RandVec(2.0);
  xs[2].bg = RandVec(0.01);
  xs[2].ba = RandVec(0.1);
  return xs;
}

inline std::vector<PreintIncrement> TestIncrements() {
  std::vector<PreintIncrement> xs(3);
  xs[1].dR = so3::Exp(Vec3(1e-8, 2e-8, -1e-8));
  xs[1].dp = Vec3(1e-7, -1e-7, 2e-7);
  xs[2].dR = so3::Exp(RandVec(0.8));
  xs[2].dp = RandVec(10.0);
  xs[2].dv = RandVec(3.0);
  xs[2].dbg = RandVec(1e-3);
  xs[2].dba = RandVec(1e-2);
  return xs;
}

/// The paper's entrywise difference: |r - e| / |r| where |r| > 1e-4, else |r - e|.
/// A non-finite estimate counts as an infinite difference (so NaN can never pass a max).
inline double EntryDiff(double r, double e) {
  if (!std::isfinite(e)) return std::numeric_limits<double>::infinity();
  return std::abs(r) > 1e-4 ? std::abs((r - e) / r) : std::abs(r - e);
}

template <typename A, typename B>
double MaxEntryDiff(const Eigen::MatrixBase<A>& ref, const Eigen::MatrixBase<B>& est) {
  double m = 0.0;
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j) m = std::max(m, EntryDiff(ref(i, j), est(i, j)));
  return m;
}

/// Max |A - B| / max(1, max|B|): a relative matrix error.
template <typename A, typename B>
double RelErr(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

inline nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  return nlohmann::json::parse(in);
}

inline Eigen::MatrixXd JsonMatrix(const nlohmann::json& j) {
  if (!j.is_array() || j.empty()) return {};
  if (!j[0].is_array()) {
    Eigen::MatrixXd m(j.size(), 1);
    for (std::size_t i = 0; i < j.size(); ++i) m(i, 0) = j[i].get<double>();
    return m;
  }
  Eigen::MatrixXd m(j.size(), j[0].size());
  for (std::size_t i = 0; i < j.size(); ++i)
    for (std::size_t k = 0; k < j[i].size(); ++k) m(i, k) = j[i][k].get<double>();
  return m;
}

inline std::string DataPath(const std::string& rel) {
  return std::string(IMUCONV_TEST_DATA_DIR) + "/" + rel;
}

/// The ten reference cases of tests/data/reference/cases (and of every folder of outputs on them).
inline constexpr const char* kReferenceCaseIds[] = {
    "aggressive-0", "aggressive-1", "jitter-0", "jitter-1", "smooth-0",
    "smooth-1",     "smooth-2",     "smooth-3", "static-0", "white-0"};

inline Vec3 JsonVec3(const nlohmann::json& j) {
  return Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
}

/// The "imu" rows [t, wx, wy, wz, ax, ay, az] of a reference case file
/// (tests/data/reference/cases).
inline std::vector<ImuSample> CaseSamples(const nlohmann::json& c) {
  std::vector<ImuSample> samples;
  for (const auto& row : c.at("imu")) {
    ImuSample s;
    s.t = row[0].get<double>();
    s.gyro = Vec3(row[1].get<double>(), row[2].get<double>(), row[3].get<double>());
    s.accel = Vec3(row[4].get<double>(), row[5].get<double>(), row[6].get<double>());
    samples.push_back(s);
  }
  return samples;
}

}  // namespace imuconv::test

namespace imuconv::test {

/// Monte Carlo check of a covariance P against samples E (one error per column).
/// With L L^T = P, the whitened sample covariance W = L^{-1} S L^{-T} of N samples has
/// diagonal entries ~ 1 +- sqrt(2/N) and off-diagonal entries ~ 0 +- sqrt(1/N) (Wishart,
/// Gaussian errors). We require every entry within 5 standard deviations: for 120 distinct
/// entries the chance that a correct P fails is below 1e-4, while a wrong block, sign or
/// factor of 2 moves the affected entries by O(1). NEES, the mean of e^T P^{-1} e, must be
/// 15 +- 5 sqrt(30/N). Nonlinearity adds bias of order sigma^2 relative, negligible here.
inline void ExpectCovarianceMatchesSamples(const Mat15& P,
                                           const Eigen::Matrix<double, 15, Eigen::Dynamic>& E) {
  const double N = static_cast<double>(E.cols());
  const Eigen::LLT<Mat15> llt(P);
  ASSERT_EQ(llt.info(), Eigen::Success) << "predicted covariance is not positive definite";
  const Eigen::Matrix<double, 15, Eigen::Dynamic> Z = llt.matrixL().solve(E);
  const Vec15 mean = Z.rowwise().mean();
  const Eigen::Matrix<double, 15, Eigen::Dynamic> Zc = Z.colwise() - mean;
  const Mat15 W = Zc * Zc.transpose() / (N - 1.0);
  const double diag_tol = 5.0 * std::sqrt(2.0 / N), off_tol = 5.0 * std::sqrt(1.0 / N);
  double worst_diag = 0.0, worst_off = 0.0;
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j) {
      if (i == j)
        worst_diag = std::max(worst_diag, std::abs(W(i, i) - 1.0));
      else
        worst_off = std::max(worst_off, std::abs(W(i, j)));
    }
  const double nees = Z.colwise().squaredNorm().mean();
  std::printf(
      "  Monte Carlo N=%d: worst |W_ii - 1| = %.3f (tol %.3f), worst |W_ij| = %.3f (tol %.3f), "
      "NEES = %.2f\n",
      static_cast<int>(N), worst_diag, diag_tol, worst_off, off_tol, nees);
  EXPECT_LT(worst_diag, diag_tol) << "whitened sample covariance:\n" << W;
  EXPECT_LT(worst_off, off_tol) << "whitened sample covariance:\n" << W;
  EXPECT_NEAR(nees, 15.0, 5.0 * std::sqrt(30.0 / N));
  // The mean of the whitened errors is ~N(0, 1/N) per entry.
  EXPECT_LT(mean.cwiseAbs().maxCoeff(), 5.0 / std::sqrt(N))
      << "mean whitened error " << mean.transpose();
}

}  // namespace imuconv::test
