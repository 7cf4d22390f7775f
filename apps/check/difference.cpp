#include "difference.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace imuconv::check {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The note's threshold: entries below 1e-4 (in RelativeAboveFloor*: of the matrix's largest)
// are judged by their absolute difference, the rest relatively.
constexpr double kFloor = 1e-4;

double NanToInf(double d) { return std::isnan(d) ? kInf : d; }

void Add(EntryDiff& out, double d) {
  d = NanToInf(d);
  out.max = std::max(out.max, d);
  out.mean += d;
}

// One entry of each difference: the summaries and the entrywise matrices are computed by these
// same two functions, so they cannot disagree.
double CorrelationScaleEntry(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user, Eigen::Index i, Eigen::Index j,
                             double largest) {
  double scale = std::sqrt(std::abs(ref(i, i) * ref(j, j)));
  if (!(scale > 0.0)) scale = largest;
  const double u = user(i, j);
  return !std::isfinite(u) ? kInf : scale > 0.0 ? std::abs(ref(i, j) - u) / scale : (u == ref(i, j) ? 0.0 : kInf);
}

double RelativeAboveFloorEntry(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user, Eigen::Index i,
                               Eigen::Index j, double small) {
  const double u = user(i, j);
  const double scale = std::max(std::abs(ref(i, j)), small);
  return !std::isfinite(u) ? kInf : scale > 0.0 ? std::abs(ref(i, j) - u) / scale : ref(i, j) == u ? 0.0 : kInf;
}

}  // namespace

EntryDiff CorrelationScaleDiff(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user) {
  EntryDiff out;
  const double largest = ref.diagonal().cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j) Add(out, CorrelationScaleEntry(ref, user, i, j, largest));
  out.mean /= static_cast<double>(ref.size());
  return out;
}

Eigen::MatrixXd CorrelationScaleEntries(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user) {
  Eigen::MatrixXd out(ref.rows(), ref.cols());
  const double largest = ref.diagonal().cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j) out(i, j) = NanToInf(CorrelationScaleEntry(ref, user, i, j, largest));
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
    for (Eigen::Index j = 0; j < ref.cols(); ++j) Add(out, RelativeAboveFloorEntry(ref, user, i, j, small));
  out.mean /= static_cast<double>(ref.size());
  return out;
}

Eigen::MatrixXd RelativeAboveFloorEntries(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user) {
  Eigen::MatrixXd out(ref.rows(), ref.cols());
  const double small = kFloor * ref.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j) out(i, j) = NanToInf(RelativeAboveFloorEntry(ref, user, i, j, small));
  return out;
}

Eigen::MatrixXd NoteEntries(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user) {
  Eigen::MatrixXd out(ref.rows(), ref.cols());
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j) {
      const double r = ref(i, j), u = user(i, j);
      out(i, j) = !std::isfinite(u) ? kInf : NanToInf(std::abs(r) > kFloor ? std::abs((r - u) / r) : std::abs(r - u));
    }
  return out;
}

EntryDiff Summarize(const Eigen::MatrixXd& entries) {
  EntryDiff out;
  for (Eigen::Index i = 0; i < entries.rows(); ++i)
    for (Eigen::Index j = 0; j < entries.cols(); ++j) Add(out, entries(i, j));
  if (entries.size() > 0) out.mean /= static_cast<double>(entries.size());
  return out;
}

}  // namespace imuconv::check
