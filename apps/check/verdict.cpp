#include "imuconv/check/verdict.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace imuconv::check {
namespace {

// The tolerances, on the max of each difference (difference.h): 1e-2 for the increment, the
// bias Jacobian and the covariance, i.e. "agrees with the explanation to 1 % entry by entry".
//
// What must pass: numbers of any scheme check compares with (references.h), computed by
// another implementation, in any registered chart. Those agree to round-off (measured, in
// this metric: GTSAM's ManifoldPreintegration with euler to 1.7e-13 on its zero-order-hold
// input and with midpoint to 9.8e-13 on its `mid` input, its TangentPreintegration with
// tangent to 4.6e-14; the project's own measurements in every chart to 3.5e-13). Numbers
// stored in single precision must pass too (GTSAM's, rounded to float: up to 3e-7), and so must
// those computed in it, which lose more over thousands of steps (of order 1e-4 relative).
//
// What must fail: a wrong chart, block order, column order or sign changes entries by their
// own size (d of order 1: a sign flip is 2, a permutation of the blocks compares unrelated
// entries), a covariance x2 is off by exactly 1 on the correlation scale, and a density used as
// a variance by nearly 1 (every variance far smaller).
//
// 1e-2 lies 100 times below the smallest of those and 100 times above single-precision
// computation. It
// also separates schemes where they differ: rk4 against midpoint-sampled numbers differs by
// 1e-3 on average over 10 s at 200 Hz, and at most by 1.7e-2 (bias Jacobian, smooth cases)
// to 5.5e-2 (fast rotation); a scheme nearer than 1e-2 is named, one farther is not taken
// for another.
const Tolerances kCheckTolerances{1e-2, 1e-2, 1e-2};  // delta, J_bias, cov

std::string Num(double v) {
  std::ostringstream o;
  o.precision(2);
  o << v;
  return o.str();
}

std::string SchemeWords(const std::string& scheme) {
  if (scheme == "euler") return "euler (zero-order hold, GTSAM's discretization)";
  if (scheme == "midpoint") return "midpoint (the mean of consecutive samples held over each step)";
  if (scheme == "rk4") return "rk4 (linear interpolation between samples)";
  if (scheme == "tangent") return "tangent (GTSAM's TangentPreintegration, zero-order hold)";
  return scheme + " (the native preintegrator)";
}

std::string Diffs(const Explanation& e) {
  return "max d: increment " + Num(e.delta.max) + ", J_bias " + Num(e.J_bias.max) +
         ", covariance " + Num(e.cov.max);
}

std::string ColumnsWords(const std::vector<std::string>& c) { return BlockList(c); }

std::string SignWords(int sign) {
  return sign > 0 ? "d/d(bias estimate)"
                  : "-d/d(bias estimate), i.e. d/d(bias correction b_hat - b)";
}

// Each block's median ratio of the user's variances to the nearest explanation's: a factor
// common to all blocks is a scaled covariance; factors that differ by block are a wrong noise
// model (a density used as a variance scales the gyro- and accelerometer-driven blocks by
// different factors).
std::string VarianceRatios(const SchemeCandidates& s, const Explanation& e,
                           const UserNumbers& user) {
  const auto it =
      std::find_if(s.covariances.begin(), s.covariances.end(),
                   [&](const CovarianceCandidate& c) { return c.convention == e.convention; });
  if (it == s.covariances.end()) return "";
  const Mat15 K = Reordered(*it, e.blocks);
  std::string out;
  for (int b = 0; b < 5; ++b) {
    double r[3];
    for (int i = 0; i < 3; ++i) r[i] = user.cov(3 * b + i, 3 * b + i) / K(3 * b + i, 3 * b + i);
    std::sort(r, r + 3);
    out += (out.empty() ? "" : ", ") + e.blocks[b] + " " + Num(r[1]);
  }
  return "the user's variances are, block by block (median over the axes), " + out +
         " times those of the nearest";
}

void CovarianceFindings(const Constraints& d, const Explanation& b, std::vector<std::string>& out) {
  if (!d.convention.empty() && b.convention == d.convention && !d.blocks.empty() &&
      b.blocks != d.blocks) {
    out.push_back("the covariance is " + b.convention + ", but the blocks are " +
                  BlockList(b.blocks) + ", not the declared " + BlockList(d.blocks) +
                  "; fix: declare cov.blocks " + BlockList(b.blocks));
    return;
  }
  std::string what = "the covariance is " + b.convention + " with blocks " + BlockList(b.blocks);
  if (!d.convention.empty() && b.convention != d.convention) {
    what += ", not the declared " + d.convention;
    if (!d.blocks.empty()) what += " " + BlockList(d.blocks);
  } else if (!d.blocks.empty() && b.blocks != d.blocks) {
    what += ", not the declared blocks " + BlockList(d.blocks);
  }
  out.push_back(what + "; fix: declare cov.convention \"" + b.convention + "\" and cov.blocks " +
                BlockList(b.blocks));
}

void JacobianFindings(const Constraints& d, const Explanation& b, std::vector<std::string>& out) {
  std::vector<std::string> fixes;
  if (!d.jacobian_convention.empty() && b.jacobian_convention != d.jacobian_convention) {
    out.push_back("J_bias's rows are in the chart " + b.jacobian_convention +
                  ", not the declared " + d.jacobian_convention);
    fixes.push_back("J_bias.convention \"" + b.jacobian_convention + "\"");
  }
  if (!d.J_bias_columns.empty() && b.J_bias_columns != d.J_bias_columns) {
    out.push_back("J_bias's columns are " + ColumnsWords(b.J_bias_columns) + ", not the declared " +
                  ColumnsWords(d.J_bias_columns));
    fixes.push_back("J_bias.cols.blocks " + ColumnsWords(b.J_bias_columns));
  }
  if (b.J_bias_sign != d.J_bias_sign && d.J_bias_sign != 0) {
    out.push_back("J_bias has the opposite sign: it is " + SignWords(b.J_bias_sign) +
                  ", while a measurements file holds d/d(bias estimate)");
    fixes.push_back("negate J_bias");
  }
  if (fixes.empty()) {
    out.push_back("J_bias is " + b.jacobian_convention + " with columns " +
                  ColumnsWords(b.J_bias_columns) + ", " + SignWords(b.J_bias_sign));
    return;
  }
  std::string f;
  for (const auto& x : fixes) f += (f.empty() ? "" : "; ") + x;
  out.push_back("fix: " + f);
}

/// What the file declared, in words ("" when nothing: a measurements file's sign alone is not
/// a declaration of charts).
std::string DeclaredWords(const Constraints& d) {
  std::vector<std::string> parts;
  if (!d.convention.empty()) parts.push_back("covariance convention " + d.convention);
  if (!d.blocks.empty()) parts.push_back("covariance blocks " + BlockList(d.blocks));
  if (!d.jacobian_convention.empty()) parts.push_back("J_bias chart " + d.jacobian_convention);
  if (!d.J_bias_columns.empty()) parts.push_back("J_bias columns " + BlockList(d.J_bias_columns));
  std::string s;
  for (std::size_t i = 0; i < parts.size(); ++i)
    s += (i == 0 ? "" : i + 1 == parts.size() ? " and " : ", ") + parts[i];
  return s;
}

std::string JacobianChoiceWords(const JacobianChoice& j) {
  return "J_bias in " + j.chart + " " + BlockList(j.columns) + (j.sign > 0 ? " +" : " -");
}

/// The explanations the search cannot tell from the one named (explain.h, Equivalents).
void EquivalentFindings(const Explanation& e, std::vector<std::string>& out) {
  if (e.equivalent.empty()) return;
  std::string named, others;
  const auto add = [&](const std::string& x) { others += (others.empty() ? "" : "; ") + x; };
  if (!e.equivalent.schemes.empty()) {
    named += "scheme " + e.scheme;
    for (const auto& s : e.equivalent.schemes) add("scheme " + s);
  }
  if (!e.equivalent.cov.empty()) {
    named += std::string(named.empty() ? "" : ", ") + "the covariance in " + e.convention + " " +
             BlockList(e.blocks);
    for (const auto& c : e.equivalent.cov)
      add("the covariance in " + c.convention + " " + BlockList(c.blocks));
  }
  if (!e.equivalent.J_bias.empty()) {
    named += std::string(named.empty() ? "" : ", ") +
             JacobianChoiceWords({e.jacobian_convention, e.J_bias_columns, e.J_bias_sign});
    for (const auto& j : e.equivalent.J_bias) add(JacobianChoiceWords(j));
  }
  out.push_back(
      "equivalent explanations, these are the same numbers (within the tie tolerance): " + named +
      "; " + others +
      "; the one named is the first in the search order (the declaration, then the registry's)");
}

void BlockFindingWords(const Explanation& e, double dt, std::vector<std::string>& out) {
  for (const BlockAnalysis* a : {&e.J_bias_blocks, &e.cov_blocks}) {
    for (const auto& f : a->findings) out.push_back(FindingWords(f, dt));
    for (const auto& u : a->unexplained)
      out.push_back(u.matrix + " block (rows " + u.rows[0] + ", cols " + u.cols[0] +
                    ") differs (max d " + Num(u.max_d) +
                    ") by no sign, scale, swap, transposition or missing terms");
  }
}

}  // namespace

const Tolerances& CheckTolerances() { return kCheckTolerances; }

std::string BlockList(const std::vector<std::string>& blocks) {
  std::string s;
  for (const auto& b : blocks) s += (s.empty() ? "" : ", ") + b;
  return "[" + s + "]";
}

Judgement Judge(const Constraints& declared, const Explanation& e_d, const Explanation& best,
                const SchemeCandidates& nearest, const UserNumbers& user, double sample_period) {
  const Tolerances& tol = kCheckTolerances;
  Judgement j;
  const std::string declared_words = DeclaredWords(declared);
  if (Score(e_d, tol) <= 1.0) {
    j.verdict = Verdict::consistent;
    j.findings.push_back("consistent with " + SchemeWords(e_d.scheme) +
                         (declared_words.empty()
                              ? " (no chart was declared; the charts are those found)"
                              : " under the declared " + declared_words) +
                         "; " + Diffs(e_d));
    if (declared.convention.empty() || declared.blocks.empty())
      j.findings.push_back("the covariance's chart was not (fully) declared; it is " +
                           e_d.convention + " with blocks " + BlockList(e_d.blocks));
    if (declared.jacobian_convention.empty() || declared.J_bias_columns.empty())
      j.findings.push_back("J_bias's chart was not (fully) declared; its rows are " +
                           e_d.jacobian_convention + ", its columns " +
                           BlockList(e_d.J_bias_columns));
    EquivalentFindings(e_d, j.findings);
    return j;
  }
  j.verdict = Verdict::inconsistent;
  if (Score(best, tol) <= 1.0) {
    j.findings.push_back((declared_words.empty()
                              ? std::string("J_bias as d/d(bias estimate), what a measurements "
                                            "file holds, does not fit (")
                              : "the declaration (" + declared_words +
                                    ", J_bias as d/d(bias estimate)) does not fit (") +
                         Diffs(e_d) + "); " + SchemeWords(best.scheme) + " explains the numbers (" +
                         Diffs(best) + ")");
    if (e_d.cov.max > tol.cov) CovarianceFindings(declared, best, j.findings);
    if (e_d.J_bias.max > tol.J_bias) JacobianFindings(declared, best, j.findings);
    EquivalentFindings(best, j.findings);
    return j;
  }
  j.findings.push_back("nothing registered explains the numbers; the nearest explanation is " +
                       SchemeWords(best.scheme) + " with the covariance in " + best.convention +
                       " " + BlockList(best.blocks) + " and J_bias in " + best.jacobian_convention +
                       " " + BlockList(best.J_bias_columns) + ", " + SignWords(best.J_bias_sign) +
                       "; " + Diffs(best) + " (tolerance " + Num(tol.cov) + ")");
  if (best.delta.max > tol.delta)
    j.findings.push_back("the increment agrees with no scheme (max d " + Num(best.delta.max) +
                         "): are the IMU samples, the interval and the bias estimate those the "
                         "measurement was made from?");
  if (best.J_bias.max > tol.J_bias)
    j.findings.push_back("no chart, column order or sign explains J_bias (nearest max d " +
                         Num(best.J_bias.max) + ")");
  if (best.cov.max > tol.cov)
    j.findings.push_back("no convention or block order explains the covariance (nearest max d " +
                         Num(best.cov.max) + "); " + VarianceRatios(nearest, best, user));
  else if (e_d.cov.max > tol.cov)
    CovarianceFindings(declared, best, j.findings);
  if (best.J_bias.max <= tol.J_bias && e_d.J_bias.max > tol.J_bias)
    JacobianFindings(declared, best, j.findings);
  BlockFindingWords(best, sample_period, j.findings);
  EquivalentFindings(best, j.findings);
  return j;
}

}  // namespace imuconv::check
