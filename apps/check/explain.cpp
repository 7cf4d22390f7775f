#include "explain.h"

#include <algorithm>
#include <array>
#include <limits>
#include <tuple>

namespace imuconv::check {
namespace {

// Differences below this are round-off: one computation by two routes (euler and the native
// manifold preintegrator; a bias Jacobian's rows through two charts whose theta, p, v blocks
// are the same) differs by at most 2.1e-13 in the measured cases. Explanations whose
// differences are all below it are equally good, and the first found is kept.
constexpr double kRoundOff = 1e-9;

double Significant(double d) { return d < kRoundOff ? 0.0 : d; }

bool Better(const EntryDiff& a, const EntryDiff& b) {
  const double am = Significant(a.max), bm = Significant(b.max);
  return am < bm || (am == bm && Significant(a.mean) < Significant(b.mean));
}

struct CovChoice {
  std::string convention;
  std::vector<std::string> blocks;
  EntryDiff d{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
};

struct JacChoice {
  std::string chart;
  std::vector<std::string> columns;
  int sign = 1;
  EntryDiff d{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
};

// The candidates in search order: only `wanted` when it is set; else `preferred` first,
// then the registry's order.
template <typename T, typename Id>
std::vector<const T*> Ordered(const std::vector<T>& all, const std::string& wanted, const std::string& preferred,
                              Id id) {
  std::vector<const T*> out;
  for (const auto& x : all)
    if (wanted.empty() ? id(x) == preferred : id(x) == wanted) out.push_back(&x);
  if (wanted.empty())
    for (const auto& x : all)
      if (id(x) != preferred) out.push_back(&x);
  return out;
}

// The candidate with the smallest difference; when none is within `tol`, the one whose
// correlation structure is nearest (CorrelationStructureDiff), which is what "nearest" can
// still mean for a covariance whose scale nothing explains.
CovChoice BestCovariance(const SchemeCandidates& s, const Mat15& user, const Constraints& c, const Constraints& prefer,
                         double tol) {
  CovChoice best, nearest_structure;
  double best_structure = std::numeric_limits<double>::infinity();
  for (const CovarianceCandidate* cand :
       Ordered(s.covariances, c.convention, prefer.convention, [](auto& x) { return x.convention; })) {
    std::vector<std::vector<std::string>> orders;
    if (!c.blocks.empty()) {
      orders.push_back(c.blocks);
    } else {
      if (!prefer.blocks.empty()) orders.push_back(prefer.blocks);
      // Every ordering of the five blocks, the chart's own first (index order = its order).
      std::array<int, 5> idx{0, 1, 2, 3, 4};
      do {
        std::vector<std::string> o;
        for (int i : idx) o.push_back(cand->labels[i]);
        orders.push_back(std::move(o));
      } while (std::next_permutation(idx.begin(), idx.end()));
    }
    const ReorderedCovarianceDiffs diffs(cand->cov, user);
    for (const auto& order : orders) {
      const auto from = ReorderedIndices(*cand, order);
      const EntryDiff d = diffs.CorrelationScale(from.data());
      if (Better(d, best.d)) best = {cand->convention, order, d};
      const double structure = diffs.CorrelationStructure(from.data());
      if (structure < best_structure) {
        best_structure = structure;
        nearest_structure = {cand->convention, order, d};
      }
    }
  }
  return best.d.max <= tol ? best : nearest_structure;
}

JacChoice BestJacobian(const SchemeCandidates& s, const Mat96& user, const Constraints& c, const Constraints& prefer) {
  JacChoice best;
  std::vector<std::vector<std::string>> all_columns = {{"bg", "ba"}, {"ba", "bg"}};
  if (prefer.J_bias_columns == all_columns[1]) std::swap(all_columns[0], all_columns[1]);
  for (const JacobianCandidate* cand :
       Ordered(s.jacobians, c.jacobian_convention, prefer.jacobian_convention, [](auto& x) { return x.chart; }))
    for (const auto& columns : all_columns) {
      if (!c.J_bias_columns.empty() && columns != c.J_bias_columns) continue;
      for (int sign : {1, -1}) {
        if (c.J_bias_sign != 0 && sign != c.J_bias_sign) continue;
        const EntryDiff d = RelativeAboveFloorDiff(Arranged(*cand, columns, sign), user);
        if (Better(d, best.d)) best = {cand->chart, columns, sign, d};
      }
    }
  return best;
}

}  // namespace

double Score(const Explanation& e, const Tolerances& tol) {
  return std::max({e.delta.max / tol.delta, e.J_bias.max / tol.J_bias, e.cov.max / tol.cov});
}

namespace {

// The ranking of Explain (round-off counted as zero): (parts beyond tolerance, sum within, sum beyond), lexicographic.
std::tuple<int, double, double> Rank(const Explanation& e, const Tolerances& tol) {
  int beyond = 0;
  double within_sum = 0.0, beyond_sum = 0.0;
  for (double r : {Significant(e.delta.max) / tol.delta, Significant(e.J_bias.max) / tol.J_bias,
                   Significant(e.cov.max) / tol.cov}) {
    if (r <= 1.0) {
      within_sum += r;
    } else {
      ++beyond;
      beyond_sum += r;
    }
  }
  return {beyond, within_sum, beyond_sum};
}

}  // namespace

Explanation Explain(const std::vector<SchemeCandidates>& schemes, const UserNumbers& user, const Constraints& c,
                    const Tolerances& tol, const Constraints& prefer) {
  Explanation best;
  std::tuple<int, double, double> best_rank;
  for (const auto& s : schemes) {
    const CovChoice cov = BestCovariance(s, user.cov, c, prefer, tol.cov);
    const JacChoice jac = BestJacobian(s, user.J_bias, c, prefer);
    Explanation e;
    e.scheme = s.scheme;
    e.convention = cov.convention;
    e.blocks = cov.blocks;
    e.cov = cov.d;
    e.jacobian_convention = jac.chart;
    e.J_bias_columns = jac.columns;
    e.J_bias_sign = jac.sign;
    e.J_bias = jac.d;
    e.delta = RelativeAboveFloorDiff(s.delta, user.delta);
    const auto rank = Rank(e, tol);
    if (best.scheme.empty() || rank < best_rank) {
      best = std::move(e);
      best_rank = rank;
    }
  }
  return best;
}

}  // namespace imuconv::check
