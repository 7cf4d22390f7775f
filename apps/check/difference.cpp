#include "difference.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace imuconv::check {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The note's threshold: entries below 1e-4 (here: of the matrix's largest) are judged by
// their absolute difference, the rest relatively.
constexpr double kFloor = 1e-4;

void Add(EntryDiff& out, double d) {
  if (std::isnan(d)) d = kInf;
  out.max = std::max(out.max, d);
  out.mean += d;
}

}  // namespace

EntryDiff CorrelationScaleDiff(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user) {
  EntryDiff out;
  const double largest = ref.diagonal().cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j) {
      double scale = std::sqrt(std::abs(ref(i, i) * ref(j, j)));
      if (!(scale > 0.0)) scale = largest;
      const double u = user(i, j);
      Add(out, !std::isfinite(u) ? kInf
               : scale > 0.0     ? std::abs(ref(i, j) - u) / scale
                                 : (u == ref(i, j) ? 0.0 : kInf));
    }
  out.mean /= static_cast<double>(ref.size());
  return out;
}

double CorrelationStructureDiff(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user) {
  const auto rho = [](const Eigen::MatrixXd& c, Eigen::Index i, Eigen::Index j) {
    const double s = c(i, i) * c(j, j);
    return s > 0.0 ? c(i, j) / std::sqrt(s) : 0.0;
  };
  double worst = 0.0;
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < i; ++j) {
      const double d = std::abs(rho(ref, i, j) - rho(user, i, j));
      worst = std::isnan(d) ? kInf : std::max(worst, d);
    }
  return worst;
}

EntryDiff RelativeAboveFloorDiff(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user) {
  EntryDiff out;
  const double small = kFloor * ref.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j) {
      const double u = user(i, j);
      const double scale = std::max(std::abs(ref(i, j)), small);
      Add(out, !std::isfinite(u) ? kInf : scale > 0.0 ? std::abs(ref(i, j) - u) / scale : ref(i, j) == u ? 0.0 : kInf);
    }
  out.mean /= static_cast<double>(ref.size());
  return out;
}

}  // namespace imuconv::check
