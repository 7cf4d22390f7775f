#include "imuconv/numeric.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace imuconv {

Mat15 CentralJacobian(const Map15& f, double h) {
  Mat15 J;
  Vec15 d = Vec15::Zero(), fp, fm;
  for (int i = 0; i < 15; ++i) {
    d[i] = h;
    f(d, fp);
    d[i] = -h;
    f(d, fm);
    d[i] = 0.0;
    J.col(i) = (fp - fm) / (2.0 * h);
  }
  return J;
}

Mat15 RiddersJacobian(const Map15& f, double h0) {
  constexpr int kTab = 10;
  constexpr double kCon = 1.4, kCon2 = kCon * kCon, kSafe = 2.0;
  Mat15 J;
  Vec15 d = Vec15::Zero(), fp, fm;
  Vec15 a[kTab][kTab];
  for (int i = 0; i < 15; ++i) {
    double h = h0;
    const auto central = [&](double step) {
      d[i] = step;
      f(d, fp);
      d[i] = -step;
      f(d, fm);
      d[i] = 0.0;
      return Vec15((fp - fm) / (2.0 * step));
    };
    a[0][0] = central(h);
    double err = std::numeric_limits<double>::max();
    Vec15 best = a[0][0];
    for (int k = 1; k < kTab; ++k) {
      h /= kCon;
      a[0][k] = central(h);
      double fac = kCon2;
      for (int j = 1; j <= k; ++j) {
        a[j][k] = (a[j - 1][k] * fac - a[j - 1][k - 1]) / (fac - 1.0);
        fac *= kCon2;
        const double e = std::max((a[j][k] - a[j - 1][k]).cwiseAbs().maxCoeff(),
                                  (a[j][k] - a[j - 1][k - 1]).cwiseAbs().maxCoeff());
        if (e <= err) {
          err = e;
          best = a[j][k];
        }
      }
      if ((a[k][k] - a[k - 1][k - 1]).cwiseAbs().maxCoeff() >= kSafe * err) break;
    }
    J.col(i) = best;
  }
  return J;
}

std::string CovarianceProblem(const Eigen::MatrixXd& C, double tol) {
  std::ostringstream o;
  o.precision(6);
  const Eigen::Index n = C.rows();
  if (C.cols() != n) {
    o << "a covariance must be square; this matrix is " << C.rows() << "x" << C.cols();
    return o.str();
  }
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      if (!std::isfinite(C(i, j))) {
        o << "entry (" << i << ", " << j << ") is not finite";
        return o.str();
      }
  for (Eigen::Index i = 0; i < n; ++i)
    if (C(i, i) < 0.0) {
      o << "diagonal entry (" << i << ", " << i << ") = " << C(i, i)
        << " is negative: a variance cannot be negative";
      return o.str();
    }
  // The correlation scale: s_i = sqrt(C_ii). A zero variance gets the smallest positive
  // scale, so that a non-zero entry in its row shows up as a correlation far above 1.
  Eigen::VectorXd s(n);
  for (Eigen::Index i = 0; i < n; ++i)
    s[i] = std::sqrt(std::max(C(i, i), std::numeric_limits<double>::min()));
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j) {
      const double r = std::abs(C(i, j) - C(j, i)) / (s[i] * s[j]);
      if (r > tol) {
        o << "not symmetric: entries (" << i << ", " << j << ") = " << C(i, j) << " and (" << j
          << ", " << i << ") = " << C(j, i) << " differ by " << r
          << " on the correlation scale (|C_ij - C_ji| / sqrt(C_ii C_jj); tolerance " << tol << ")";
        return o.str();
      }
    }
  const Eigen::MatrixXd sym = 0.5 * (C + C.transpose());
  const Eigen::MatrixXd R = s.asDiagonal().inverse() * sym * s.asDiagonal().inverse();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig_r(R, Eigen::EigenvaluesOnly);
  const double min_r = eig_r.eigenvalues().minCoeff();
  if (min_r < -tol) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig_c(sym, Eigen::EigenvaluesOnly);
    o << "not positive semi-definite: smallest eigenvalue " << eig_c.eigenvalues().minCoeff()
      << " (of the correlation matrix C_ij / sqrt(C_ii C_jj): " << min_r << "; tolerance " << -tol
      << ")";
    return o.str();
  }
  return {};
}

}  // namespace imuconv
