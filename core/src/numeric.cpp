#include "imuconv/numeric.h"

#include <cmath>
#include <limits>

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

}  // namespace imuconv
