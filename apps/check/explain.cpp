#include "imuconv/check/explain.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <tuple>

namespace imuconv::check {
namespace {

// Two differences are the same number (a tie) when both are below kRoundOff, or when they
// differ by at most kTieRelative of the larger.
//  - Absolute: one computation by two routes (euler and the native manifold preintegrator; a
//    bias Jacobian's rows through two charts whose theta, p, v blocks are the same) differs by
//    at most 2.1e-13 in the measured cases, on differences that are themselves round-off.
//  - Relative: on differences of order 1 round-off scales with them: the same J_bias with one
//    block negated scores 2.0000000000000133 under its declared chart and 2.000000000000004
//    with every block negated (5e-15 relative), and an absolute 1e-9 read that as a real
//    difference (issue 23). 1e-9 is 1e4 times the double round-off these sums of a few
//    hundred terms accumulate, and far below any real difference between two explanations
//    (a wrong sign, chart or order changes d by order 1, two schemes by 1e-3 and more).
constexpr double kRoundOff = 1e-9;
constexpr double kTieRelative = 1e-9;

/// -1: a is smaller, 0: tied, 1: b is smaller (infinities and NaNs are equal only to themselves).
int Compare(double a, double b) {
  if (a < kRoundOff && b < kRoundOff) return 0;
  if (std::isfinite(a) && std::isfinite(b) &&
      std::abs(a - b) <= kTieRelative * std::max(std::abs(a), std::abs(b)))
    return 0;
  if (a == b) return 0;
  return a < b ? -1 : 1;
}

/// Lexicographic Compare of two keys of equal length.
int CompareKeys(const std::vector<double>& a, const std::vector<double>& b) {
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
    if (const int c = Compare(a[i], b[i]); c != 0) return c;
  return 0;
}

double Significant(double d) { return d < kRoundOff ? 0.0 : d; }

/// One scored candidate of a part.
template <typename Choice>
struct Scored {
  Choice choice;
  EntryDiff d;
  BlockAnalysis blocks;
  std::vector<double> key;
};

/// The best candidate of one part (covariance or J_bias): its differences, its blocks, its
/// choice and the other choices tied with it.
template <typename Choice>
struct PartResult {
  EntryDiff d;
  BlockAnalysis blocks;
  Choice choice;
  std::vector<Choice> tied;
};
using CovResult = PartResult<CovarianceChoice>;
using JacResult = PartResult<JacobianChoice>;

/// The best of `all` by key (the first of the tied ones) and the others tied with it. A
/// candidate without a key was left unanalyzed because it cannot win (AnalyzeThoseThatCanWin)
/// and takes no part.
template <typename Choice>
PartResult<Choice> Pick(const std::vector<Scored<Choice>>& all) {
  const Scored<Choice>* best = nullptr;
  for (const auto& x : all)
    if (!x.key.empty() && (!best || CompareKeys(x.key, best->key) < 0)) best = &x;
  PartResult<Choice> out;
  out.d = best->d;
  out.blocks = best->blocks;
  out.choice = best->choice;
  for (const auto& x : all)
    if (&x != best && !x.key.empty() && CompareKeys(x.key, best->key) == 0 &&
        !(x.choice == best->choice) &&
        std::find(out.tied.begin(), out.tied.end(), x.choice) == out.tied.end())
      out.tied.push_back(x.choice);
  return out;
}

/// Calls `analyze(i)` (which sets candidate i's BlockKey and returns its first entry, the
/// corrections counted) on exactly the candidates that can be the pick or tied with it, so the
/// pick and its ties are those of analyzing every one; `beyond[i]` is candidate i's blocks
/// beyond tolerance (block_findings.h), a lower bound of its corrections (each counts one or
/// two).
//
// Why that is exact: the first key entry is a whole number, compared exactly (Compare's tie
// tolerances are both below 1), so with m the least count over all candidates, a candidate
// counting more than m compares greater than any counting m: it is never the final pick nor
// tied with it, and Pick, which goes through the candidates in search order keeping the first
// strictly smaller one, reaches the same pick through the candidates counting m alone.
// Candidates are analyzed by increasing bound, and the least count found so far is at least
// m, so every one whose bound exceeds it counts more than m. Those analyzed in vain (bound
// below that count, count above m) are ranked by Pick as before, and lose as before.
template <typename Analyze>
void AnalyzeThoseThatCanWin(const std::vector<int>& beyond, Analyze analyze) {
  std::vector<std::size_t> order(beyond.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return beyond[a] < beyond[b]; });
  double least = std::numeric_limits<double>::infinity();
  for (const std::size_t i : order) {
    if (static_cast<double>(beyond[i]) > least) break;
    least = std::min(least, analyze(i));
  }
}

/// The key of a part when some candidate is within tolerance: max d, then mean d.
std::vector<double> WithinKey(const EntryDiff& d) { return {0.0, 0.0, 0.0, 0.0, d.max, d.mean}; }

/// The key when none is: the fewest corrections, counting a block beyond tolerance that a
/// block finding explains as one and one that none explains as two (it needs more than any one
/// kind), then the fewest unexplained, the smallest sum of the blocks' max d, then `structure`
/// (0 for J_bias), max d, mean d. Counting an unexplained block once would let a wrong block
/// order win by fewer blocks beyond tolerance that nothing explains (a density used as a
/// variance: 9 blocks, 2 unexplained, in a wrong order against 10, all explained by a scale, in
/// the right one); counting only the unexplained would let a wrong order win by fitting
/// meaningless scales (OKVIS2's covariance: 6 blocks, 3 unexplained in its own order against 9,
/// 2 unexplained, with factors of 1e4 where its bias and rotation blocks are exchanged).
std::vector<double> BlockKey(const BlockAnalysis& a, double structure, const EntryDiff& d) {
  const double unexplained = static_cast<double>(a.unexplained.size());
  return {a.mismatched + unexplained, unexplained, a.mismatch_sum, structure, d.max, d.mean};
}

// The candidates in search order: only `wanted` when it is set; else `preferred` first,
// then the registry's order.
template <typename T, typename Id>
std::vector<const T*> Ordered(const std::vector<T>& all, const std::string& wanted,
                              const std::string& preferred, Id id) {
  std::vector<const T*> out;
  for (const auto& x : all)
    if (wanted.empty() ? id(x) == preferred : id(x) == wanted) out.push_back(&x);
  if (wanted.empty())
    for (const auto& x : all)
      if (id(x) != preferred) out.push_back(&x);
  return out;
}

/// One block order of one covariance candidate: the order as the candidate's row map (block b
/// of the order is the candidate's block from[3b] / 3), its labels written out only for what
/// is reported or analyzed; its mean d computed only where a comparison or the report needs it
/// (its max is the block maxima's, difference.h).
struct CovarianceOrder {
  std::size_t candidate;
  std::array<Eigen::Index, 15> from;
  EntryDiff d;
  bool mean_known = false;
  int beyond = 0;  // blocks beyond tolerance (block_findings.h)
  double structure = 0.0;
  BlockAnalysis blocks;
  std::vector<double> key;  // when no order of any candidate is within tolerance: BlockKey
};

CovResult BestCovariance(const SchemeCandidates& s, const Mat15& user, const Constraints& c,
                         const Constraints& prefer, double tol) {
  const std::vector<const CovarianceCandidate*> candidates =
      Ordered(s.covariances, c.convention, prefer.convention, [](auto& x) { return x.convention; });
  // Each candidate's differences from the user's numbers, tabled once for all its orders.
  std::vector<ReorderedCovarianceDiffs> diffs;
  diffs.reserve(candidates.size());
  std::vector<CovarianceOrder> all;
  bool any_within = false;
  const auto add = [&](std::size_t k, const std::array<Eigen::Index, 15>& from) {
    CovarianceOrder x{k, from, {}, false, 0, 0.0, {}, {}};
    const ReorderedCovarianceDiffs::BlockMaxD block_max_d = diffs[k].BlockMaxima(from.data());
    for (const auto& row : block_max_d)
      for (double m : row) x.d.max = std::max(x.d.max, m);
    x.beyond = diffs[k].ReferenceFinite() ? CovarianceBlocksBeyond(block_max_d, tol) : 0;
    any_within = any_within || x.d.max <= tol;
    all.push_back(std::move(x));
  };
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const CovarianceCandidate& cand = *candidates[k];
    diffs.emplace_back(cand.cov, user);
    if (!c.blocks.empty()) {
      add(k, ReorderedIndices(cand, c.blocks));
      continue;
    }
    if (!prefer.blocks.empty()) add(k, ReorderedIndices(cand, prefer.blocks));
    // Every ordering of the five blocks, the chart's own first (index order = its order), the
    // preferred one not twice.
    std::array<int, 5> idx{0, 1, 2, 3, 4};
    do {
      bool is_preferred = prefer.blocks.size() == 5;
      for (std::size_t b = 0; b < 5 && is_preferred; ++b)
        is_preferred = cand.labels[static_cast<std::size_t>(idx[b])] == prefer.blocks[b];
      if (is_preferred) continue;
      std::array<Eigen::Index, 15> from{};
      for (int b = 0; b < 5; ++b)
        for (int r = 0; r < 3; ++r) from[3 * b + r] = 3 * idx[static_cast<std::size_t>(b)] + r;
      add(k, from);
    } while (std::next_permutation(idx.begin(), idx.end()));
  }
  const auto with_mean = [&](CovarianceOrder& x) -> const EntryDiff& {
    if (!x.mean_known) {
      x.d = diffs[x.candidate].CorrelationScale(x.from.data());
      x.mean_known = true;
    }
    return x.d;
  };
  const auto choice = [&](const CovarianceOrder& x) {
    const CovarianceCandidate& cand = *candidates[x.candidate];
    CovarianceChoice out{cand.convention, {}};
    for (int b = 0; b < 5; ++b)
      out.blocks.push_back(cand.labels[static_cast<std::size_t>(x.from[3 * b] / 3)]);
    return out;
  };
  // The keys compared (Pick): WithinKey, whose first four entries are zero, so the max and then
  // the mean; else BlockKey, for the analyzed orders only.
  std::function<int(CovarianceOrder&, CovarianceOrder&)> compare;
  std::function<bool(const CovarianceOrder&)> takes_part;
  if (any_within) {
    compare = [&](CovarianceOrder& a, CovarianceOrder& b) {
      if (const int m = Compare(a.d.max, b.d.max); m != 0) return m;
      return Compare(with_mean(a).mean, with_mean(b).mean);
    };
    takes_part = [](const CovarianceOrder&) { return true; };
  } else {
    // What is wrong block by block (block_findings.h), under each order that can win.
    std::vector<int> beyond(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) beyond[i] = all[i].beyond;
    AnalyzeThoseThatCanWin(beyond, [&](std::size_t i) {
      CovarianceOrder& x = all[i];
      const CovarianceCandidate& cand = *candidates[x.candidate];
      Mat15 K;
      for (int b = 0; b < 15; ++b)
        for (int a = 0; a < 15; ++a) K(a, b) = cand.cov(x.from[a], x.from[b]);
      x.structure = diffs[x.candidate].CorrelationStructure(x.from.data());
      x.blocks = AnalyzeCovarianceBlocks(K, user, choice(x).blocks, tol);
      x.key = BlockKey(x.blocks, x.structure, with_mean(x));
      return x.key.front();
    });
    compare = [](CovarianceOrder& a, CovarianceOrder& b) { return CompareKeys(a.key, b.key); };
    takes_part = [](const CovarianceOrder& x) { return !x.key.empty(); };
  }
  // Pick's rule (the first of the smallest, then the others tied with it), on these orders.
  CovarianceOrder* best = nullptr;
  for (auto& x : all)
    if (takes_part(x) && (!best || compare(x, *best) < 0)) best = &x;
  CovResult out;
  out.d = with_mean(*best);
  out.blocks = best->blocks;
  out.choice = choice(*best);
  for (auto& x : all) {
    if (&x == best || !takes_part(x) || compare(x, *best) != 0) continue;
    CovarianceChoice other = choice(x);
    if (!(other == out.choice) &&
        std::find(out.tied.begin(), out.tied.end(), other) == out.tied.end())
      out.tied.push_back(std::move(other));
  }
  return out;
}

JacResult BestJacobian(const SchemeCandidates& s, const Mat96& user, const Constraints& c,
                       const Constraints& prefer, double tol) {
  std::vector<Scored<JacobianChoice>> all;
  std::vector<Mat96> arranged;
  std::vector<const JacobianCandidate*> sources;
  std::vector<std::vector<std::string>> all_columns = {{"bg", "ba"}, {"ba", "bg"}};
  if (prefer.J_bias_columns == all_columns[1]) std::swap(all_columns[0], all_columns[1]);
  bool any_within = false;
  for (const JacobianCandidate* cand :
       Ordered(s.jacobians, c.jacobian_convention, prefer.jacobian_convention,
               [](auto& x) { return x.chart; }))
    for (const auto& columns : all_columns) {
      if (!c.J_bias_columns.empty() && columns != c.J_bias_columns) continue;
      for (int sign : {1, -1}) {
        if (c.J_bias_sign != 0 && sign != c.J_bias_sign) continue;
        arranged.push_back(Arranged(*cand, columns, sign));
        sources.push_back(cand);
        Scored<JacobianChoice> x{
            {cand->chart, columns, sign}, RelativeAboveFloorDiff(arranged.back(), user), {}, {}};
        any_within = any_within || x.d.max <= tol;
        all.push_back(std::move(x));
      }
    }
  if (any_within) {
    for (auto& x : all) x.key = WithinKey(x.d);
    return Pick(all);
  }
  std::vector<int> beyond(all.size());
  for (std::size_t i = 0; i < all.size(); ++i)
    beyond[i] = JacobianBlocksBeyond(arranged[i], user, tol);
  AnalyzeThoseThatCanWin(beyond, [&](std::size_t i) {
    auto& x = all[i];
    x.blocks = AnalyzeJacobianBlocks(arranged[i], user, sources[i]->rows, x.choice.columns, tol);
    x.key = BlockKey(x.blocks, 0.0, x.d);
    return x.key.front();
  });
  return Pick(all);
}

}  // namespace

double Score(const Explanation& e, const Tolerances& tol) {
  return std::max({e.delta.max / tol.delta, e.J_bias.max / tol.J_bias, e.cov.max / tol.cov});
}

namespace {

// The ranking of Explain across schemes (round-off counted as zero): parts beyond tolerance,
// the sum of the parts within it, then blocks beyond tolerance, unexplained blocks, the sum of
// the parts beyond; compared as CompareKeys does. The parts a scheme explains come before the
// block count: a scheme whose covariance lacks whole blocks (Basalt's has no bias random walk)
// would otherwise "explain" a covariance by fewer, meaningless block findings.
std::vector<double> Rank(const Explanation& e, const Tolerances& tol) {
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
  const double mismatched =
      static_cast<double>(e.J_bias_blocks.mismatched + e.cov_blocks.mismatched);
  const double unexplained =
      static_cast<double>(e.J_bias_blocks.unexplained.size() + e.cov_blocks.unexplained.size());
  return {static_cast<double>(beyond), within_sum, mismatched, unexplained, beyond_sum};
}

}  // namespace

Explanation Explain(const std::vector<SchemeCandidates>& schemes, const UserNumbers& user,
                    const Constraints& c, const Tolerances& tol, const Constraints& prefer) {
  std::vector<Explanation> per_scheme;
  std::vector<std::vector<double>> ranks;
  for (const auto& s : schemes) {
    const CovResult cov = BestCovariance(s, user.cov, c, prefer, tol.cov);
    const JacResult jac = BestJacobian(s, user.J_bias, c, prefer, tol.J_bias);
    Explanation e;
    e.scheme = s.scheme;
    e.convention = cov.choice.convention;
    e.blocks = cov.choice.blocks;
    e.cov = cov.d;
    e.cov_blocks = cov.blocks;
    e.jacobian_convention = jac.choice.chart;
    e.J_bias_columns = jac.choice.columns;
    e.J_bias_sign = jac.choice.sign;
    e.J_bias = jac.d;
    e.J_bias_blocks = jac.blocks;
    e.equivalent.cov = cov.tied;
    e.equivalent.J_bias = jac.tied;
    e.delta = RelativeAboveFloorDiff(s.delta, user.delta);
    ranks.push_back(Rank(e, tol));
    per_scheme.push_back(std::move(e));
  }
  std::size_t best = 0;
  for (std::size_t i = 1; i < per_scheme.size(); ++i)
    if (CompareKeys(ranks[i], ranks[best]) < 0) best = i;
  Explanation out = per_scheme.at(best);
  // Schemes tied with the pick whose numbers are the pick's to the tie tolerance in every
  // part are the same numbers by another route (euler and manifold).
  for (std::size_t i = 0; i < per_scheme.size(); ++i) {
    if (i == best || CompareKeys(ranks[i], ranks[best]) != 0) continue;
    const Explanation& e = per_scheme[i];
    if (Compare(e.delta.max, out.delta.max) == 0 && Compare(e.J_bias.max, out.J_bias.max) == 0 &&
        Compare(e.cov.max, out.cov.max) == 0 && Compare(e.J_bias.mean, out.J_bias.mean) == 0 &&
        Compare(e.cov.mean, out.cov.mean) == 0)
      out.equivalent.schemes.push_back(e.scheme);
  }
  return out;
}

}  // namespace imuconv::check
