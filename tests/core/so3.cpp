// SO(3) maps at |phi| = 0, 1e-9, 1e-4, 1 and pi - 1e-6: Exp against a long-double series,
// Log(Exp(phi)) = phi, Jacobians against central differences and their inverses.
#include <gtest/gtest.h>

#include <cmath>

#include "imuconv/so3.h"
#include "imuconv/types.h"

namespace {

using imuconv::Mat3;
using imuconv::Vec3;
namespace so3 = imuconv::so3;

const double kAngles[] = {0.0, 1e-9, 1e-4, 1.0, M_PI - 1e-6};

Vec3 Axis() { return Vec3(0.3, -0.5, 0.8).normalized(); }

// exp([phi]x) by a long-double Taylor series with scaling and squaring: independent of
// the closed forms under test.
Mat3 ExpReference(const Vec3& phi) {
  using M = Eigen::Matrix<long double, 3, 3>;
  M S;
  S << 0, -phi.z(), phi.y(), phi.z(), 0, -phi.x(), -phi.y(), phi.x(), 0;
  int squarings = 0;
  while (S.cwiseAbs().maxCoeff() > 0.01L) {
    S /= 2.0L;
    ++squarings;
  }
  M sum = M::Identity(), term = M::Identity();
  for (int k = 1; k < 30; ++k) {
    term = term * S / static_cast<long double>(k);
    sum += term;
  }
  for (int i = 0; i < squarings; ++i) sum = sum * sum;
  return sum.cast<double>();
}

TEST(So3, ExpMatchesSeries) {
  for (double a : kAngles) {
    const Vec3 phi = a * Axis();
    // 4 ulps of a unit-entry matrix.
    EXPECT_LT((so3::Exp(phi) - ExpReference(phi)).cwiseAbs().maxCoeff(), 1e-15) << "angle " << a;
  }
}

TEST(So3, LogInvertsExp) {
  for (double a : kAngles) {
    const Vec3 phi = a * Axis();
    // Near pi the rotation matrix itself carries only ~1e-16 absolute information about the
    // angle; relative to |phi| the round trip is exact to a few ulps everywhere.
    EXPECT_LT((so3::Log(so3::Exp(phi)) - phi).norm(), 4e-16 * std::max(1.0, a) + 1e-30)
        << "angle " << a;
  }
}

TEST(So3, RightJacobianMatchesCentralDifferences) {
  for (double a : kAngles) {
    const Vec3 phi = a * Axis();
    const Mat3 R = so3::Exp(phi);
    Mat3 num;
    const double h = 1e-6;
    for (int i = 0; i < 3; ++i) {
      Vec3 e = Vec3::Zero();
      e[i] = h;
      // Exp(phi + e) = Exp(phi) Exp(Jr e): the column is Log(R^T Exp(phi + e)) / e.
      num.col(i) = (so3::Log(R.transpose() * so3::Exp(phi + e)) -
                    so3::Log(R.transpose() * so3::Exp(phi - e))) /
                   (2 * h);
    }
    // Central differences with h = 1e-6: truncation O(h^2) ~ 1e-12, rounding ~1e-16/h = 1e-10.
    EXPECT_LT((so3::Jr(phi) - num).cwiseAbs().maxCoeff(), 1e-9) << "angle " << a;
    EXPECT_LT((so3::Jl(phi) - so3::Jr(-phi)).cwiseAbs().maxCoeff(), 1e-15) << "angle " << a;
  }
}

TEST(So3, InverseJacobiansInvert) {
  for (double a : kAngles) {
    const Vec3 phi = a * Axis();
    // Jr^{-1} grows like pi/(pi - a) near pi (~3e6 at pi - 1e-6), so the product's error
    // scales with that condition number times machine epsilon.
    const double cond = (a > 3.0) ? 1.0 / (M_PI - a) : 1.0;
    EXPECT_LT((so3::Jr(phi) * so3::JrInv(phi) - Mat3::Identity()).cwiseAbs().maxCoeff(),
              1e-15 * cond * 10)
        << a;
    EXPECT_LT((so3::Jl(phi) * so3::JlInv(phi) - Mat3::Identity()).cwiseAbs().maxCoeff(),
              1e-15 * cond * 10)
        << a;
  }
}

TEST(So3, SeriesBranchIsContinuous) {
  // Both sides of the Taylor/closed-form switch at |phi| = 0.1: the arguments differ by
  // 2e-12 and every derivative is O(1), so the values may differ by ~2e-12; a wrong series
  // coefficient would show up at 1e-8 or more.
  const Vec3 below = (0.1 - 1e-12) * Axis(), above = (0.1 + 1e-12) * Axis();
  EXPECT_LT((so3::Jr(below) - so3::Jr(above)).cwiseAbs().maxCoeff(), 1e-11);
  EXPECT_LT((so3::JrInv(below) - so3::JrInv(above)).cwiseAbs().maxCoeff(), 1e-11);
  EXPECT_LT((so3::Exp(below) - so3::Exp(above)).cwiseAbs().maxCoeff(), 1e-11);
}

}  // namespace
