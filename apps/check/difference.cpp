#include "imuconv/check/difference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

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

/// Entries read in place (difference.h); the second matrix of a comparison must have the
/// first's shape (every caller compares a candidate with the user's matrix of the same block
/// layout).
struct Entries : ColumnMajorEntries {
  explicit Entries(MatrixView m) : ColumnMajorEntries(m) {}
  Entries(MatrixView m, MatrixView shape_of) : ColumnMajorEntries(m) {
    if (m.rows() != shape_of.rows() || m.cols() != shape_of.cols())
      throw std::logic_error("check: compared matrices differ in shape");
  }
};

// One entry of each difference: the summaries, the search and the entrywise matrices are
// computed by these same functions, so they cannot disagree.
double CorrelationScaleValue(double r, double u, double scale, double largest) {
  if (!(scale > 0.0)) scale = largest;
  return !std::isfinite(u) ? kInf : scale > 0.0 ? std::abs(r - u) / scale : (u == r ? 0.0 : kInf);
}
double CorrelationScaleOf(double var_i, double var_j) { return std::sqrt(std::abs(var_i * var_j)); }
/// rho_ij = C_ij / sqrt(C_ii C_jj), 0 where that product is not positive.
double Correlation(double c_ij, double var_i, double var_j) {
  const double s = var_i * var_j;
  return s > 0.0 ? c_ij / std::sqrt(s) : 0.0;
}

double RelativeAboveFloorEntry(const Entries& ref, const Entries& user, Eigen::Index i,
                               Eigen::Index j, double small) {
  const double u = user(i, j);
  const double scale = std::max(std::abs(ref(i, j)), small);
  return !std::isfinite(u) ? kInf
         : scale > 0.0     ? std::abs(ref(i, j) - u) / scale
         : ref(i, j) == u  ? 0.0
                           : kInf;
}

}  // namespace

Eigen::MatrixXd CorrelationScaleEntries(MatrixView ref, MatrixView user) {
  Eigen::MatrixXd out(ref.rows(), ref.cols());
  const double largest = ref.diagonal().cwiseAbs().maxCoeff();
  const Entries r(ref), u(user, ref);
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j)
      out(i, j) = NanToInf(
          CorrelationScaleValue(r(i, j), u(i, j), CorrelationScaleOf(r(i, i), r(j, j)), largest));
  return out;
}

ReorderedCovarianceDiffs::ReorderedCovarianceDiffs(MatrixView ref, MatrixView user)
    : ref_(ref),
      user_(user),
      scale_(ref.rows(), ref.cols()),
      rho_ref_(ref.rows(), ref.cols()),
      rho_user_(user.rows(), user.cols()) {
  if (ref.rows() != ref.cols() || user.rows() != ref.rows() || user.cols() != ref.cols())
    throw std::logic_error("check: compared covariances differ in shape");
  largest_ = ref.diagonal().cwiseAbs().maxCoeff();
  ref_finite_ = ref.allFinite();
  // K_ii K_jj of the reordered K is ref(a, a) ref(b, b) for its indices a, b: the same operands.
  for (Eigen::Index j = 0; j < ref.cols(); ++j)
    for (Eigen::Index i = 0; i < ref.rows(); ++i) {
      scale_(i, j) = CorrelationScaleOf(ref(i, i), ref(j, j));
      rho_ref_(i, j) = Correlation(ref(i, j), ref(i, i), ref(j, j));
      rho_user_(i, j) = Correlation(user(i, j), user(i, i), user(j, j));
    }
  if (ref.rows() != 15) return;
  block_table_.assign(625, 0.0);
  const Eigen::Index n = 15;
  const double *r = ref_.data(), *u = user_.data(), *scale = scale_.data();
  for (int a = 0; a < 5; ++a)
    for (int b = 0; b < 5; ++b)
      for (int pa = 0; pa < 5; ++pa)
        for (int pb = 0; pb < 5; ++pb) {
          double m = 0.0;
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
              const Eigen::Index ab = (3 * pa + i) + (3 * pb + j) * n;
              m = std::max(m, NanToInf(CorrelationScaleValue(
                                  r[ab], u[(3 * a + i) + (3 * b + j) * n], scale[ab], largest_)));
            }
          block_table_[static_cast<std::size_t>(((a * 5 + b) * 5 + pa) * 5 + pb)] = m;
        }
}

ReorderedCovarianceDiffs::BlockMaxD ReorderedCovarianceDiffs::BlockMaxima(
    const Eigen::Index* from) const {
  if (block_table_.empty())
    throw std::logic_error("check: block maxima of a covariance that is not 15x15");
  BlockMaxD out;
  for (int a = 0; a < 5; ++a)
    for (int b = 0; b < 5; ++b)
      out[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] =
          block_table_[static_cast<std::size_t>(((a * 5 + b) * 5 + from[3 * a] / 3) * 5 +
                                                from[3 * b] / 3)];
  return out;
}

// The two loops below run 120 times per candidate and measurement: they index the column-major
// storage directly (Eigen's operator() is a checked call per entry in the sanitized -O1 build).
EntryDiff ReorderedCovarianceDiffs::CorrelationScale(const Eigen::Index* from) const {
  EntryDiff out;
  const Eigen::Index n = ref_.rows();
  const double *ref = ref_.data(), *user = user_.data(), *scale = scale_.data();
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) {
      const Eigen::Index ab = from[i] + from[j] * n;
      Add(out, CorrelationScaleValue(ref[ab], user[i + j * n], scale[ab], largest_));
    }
  out.mean /= static_cast<double>(ref_.size());
  return out;
}

double ReorderedCovarianceDiffs::CorrelationStructure(const Eigen::Index* from) const {
  double worst = 0.0;
  const Eigen::Index n = ref_.rows();
  const double *rho_ref = rho_ref_.data(), *rho_user = rho_user_.data();
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < i; ++j) {
      const double d = std::abs(rho_ref[from[i] + from[j] * n] - rho_user[i + j * n]);
      worst = std::isnan(d) ? kInf : std::max(worst, d);
    }
  return worst;
}

EntryDiff RelativeAboveFloorDiff(MatrixView ref, MatrixView user) {
  EntryDiff out;
  const double small = kFloor * ref.cwiseAbs().maxCoeff();
  const Entries r(ref), u(user, ref);
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j)
      Add(out, RelativeAboveFloorEntry(r, u, i, j, small));
  out.mean /= static_cast<double>(ref.size());
  return out;
}

Eigen::MatrixXd RelativeAboveFloorEntries(MatrixView ref, MatrixView user) {
  Eigen::MatrixXd out(ref.rows(), ref.cols());
  const double small = kFloor * ref.cwiseAbs().maxCoeff();
  const Entries r(ref), u(user, ref);
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j)
      out(i, j) = NanToInf(RelativeAboveFloorEntry(r, u, i, j, small));
  return out;
}

Eigen::MatrixXd NoteEntries(MatrixView ref, MatrixView user) {
  Eigen::MatrixXd out(ref.rows(), ref.cols());
  for (Eigen::Index i = 0; i < ref.rows(); ++i)
    for (Eigen::Index j = 0; j < ref.cols(); ++j) {
      const double r = ref(i, j), u = user(i, j);
      out(i, j) = !std::isfinite(u)
                      ? kInf
                      : NanToInf(std::abs(r) > kFloor ? std::abs((r - u) / r) : std::abs(r - u));
    }
  return out;
}

EntryDiff Summarize(MatrixView entries) {
  EntryDiff out;
  for (Eigen::Index i = 0; i < entries.rows(); ++i)
    for (Eigen::Index j = 0; j < entries.cols(); ++j) Add(out, entries(i, j));
  if (entries.size() > 0) out.mean /= static_cast<double>(entries.size());
  return out;
}

}  // namespace imuconv::check
