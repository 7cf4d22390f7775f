#include "imuconv/check/block_findings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace imuconv::check {
namespace {

constexpr double kBlockInf = std::numeric_limits<double>::infinity();

// The note's threshold (difference.cpp): J_bias entries below 1e-4 of its largest are judged
// by their absolute difference.
constexpr double kBlockFloor = 1e-4;

struct Block {
  Eigen::Index r0, c0;
  std::string row, col;
};

ColumnMajorEntries In(MatrixView m) { return ColumnMajorEntries(m); }

/// The denominators of a part's difference, entry by entry, of the reference K: at most 15x15
/// (the covariance; J_bias is 9x6), held without a heap allocation.
using Scales = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 15, 15>;
ColumnMajorEntries In(const Scales& s) { return ColumnMajorEntries(s.data(), s.outerStride()); }
Scales JacobianScales(MatrixView K) {
  const double small = kBlockFloor * K.cwiseAbs().maxCoeff();
  return K.cwiseAbs().cwiseMax(small);
}
Scales CovarianceScales(MatrixView K) {
  const double largest = K.diagonal().cwiseAbs().maxCoeff();
  const ColumnMajorEntries k = In(K);
  Scales S(K.rows(), K.cols());
  for (Eigen::Index j = 0; j < K.cols(); ++j)
    for (Eigen::Index i = 0; i < K.rows(); ++i) {
      const double s = std::sqrt(std::abs(k(i, i) * k(j, j)));
      S(i, j) =
          s > 0.0 ? s : largest;  // a state no noise reaches: judged against the largest variance
    }
  return S;
}

/// max over block B of |f K(src) - U(i, j)| / (|f| S(src)); src(i, j) maps B's entry to K's.
/// f = 0 (missing): |U(i, j)| / S(i, j). Not finite (a NaN) counts as infinite.
template <typename Src>
double Residual(const ColumnMajorEntries& K, const ColumnMajorEntries& U,
                const ColumnMajorEntries& S, const Block& B, double f, Src src) {
  double worst = 0.0;
  for (Eigen::Index i = B.r0; i < B.r0 + 3; ++i)
    for (Eigen::Index j = B.c0; j < B.c0 + 3; ++j) {
      double d;
      if (f == 0.0) {
        d = S(i, j) > 0.0 ? std::abs(U(i, j)) / S(i, j) : (U(i, j) == 0.0 ? 0.0 : kBlockInf);
      } else {
        const auto [a, b] = src(i, j);
        const double s = std::abs(f) * S(a, b);
        d = s > 0.0 ? std::abs(f * K(a, b) - U(i, j)) / s
                    : (f * K(a, b) == U(i, j) ? 0.0 : kBlockInf);
      }
      if (!(d <= worst)) worst = std::isnan(d) ? kBlockInf : std::max(worst, d);
    }
  return worst;
}

std::pair<Eigen::Index, Eigen::Index> Same(Eigen::Index i, Eigen::Index j) { return {i, j}; }

/// Least-squares f of U = f K over block B, each entry weighted by 1/S^2 (the metric's own
/// weights); 0 when K's block is zero.
double FittedScale(const ColumnMajorEntries& K, const ColumnMajorEntries& U,
                   const ColumnMajorEntries& S, const Block& B) {
  double ku = 0.0, kk = 0.0;
  for (Eigen::Index i = B.r0; i < B.r0 + 3; ++i)
    for (Eigen::Index j = B.c0; j < B.c0 + 3; ++j) {
      if (!(S(i, j) > 0.0)) continue;
      const double w = 1.0 / (S(i, j) * S(i, j));
      ku += w * K(i, j) * U(i, j);
      kk += w * K(i, j) * K(i, j);
    }
  return kk > 0.0 && std::isfinite(ku) ? ku / kk : 0.0;
}

/// Block B's max d as the numbers are (no finding undone).
double MaxD(const ColumnMajorEntries& K, const ColumnMajorEntries& U, const ColumnMajorEntries& S,
            const Block& B) {
  return Residual(K, U, S, B, 1.0, Same);
}

bool Beyond(double max_d, double tol) { return !(max_d <= tol); }

/// The blocks of a Jacobian (three row blocks x two column blocks) and of a covariance (on and
/// above the diagonal: the one below is the same numbers transposed, the user's covariance being
/// symmetric, the measurement reader's check), labelled when labels are given.
std::vector<Block> JacobianBlocks(const std::vector<std::string>* row_labels,
                                  const std::vector<std::string>* col_labels) {
  std::vector<Block> blocks;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 2; ++c)
      blocks.push_back({3 * r, 3 * c, row_labels ? row_labels->at(r) : std::string(),
                        col_labels ? col_labels->at(c) : std::string()});
  return blocks;
}
std::vector<Block> CovarianceBlocks(const std::vector<std::string>& labels) {
  std::vector<Block> blocks;
  for (int a = 0; a < 5; ++a)
    for (int b = a; b < 5; ++b) blocks.push_back({3 * a, 3 * b, labels.at(a), labels.at(b)});
  return blocks;
}

int CountBeyond(MatrixView K, MatrixView U, const Scales& S, const std::vector<Block>& blocks,
                double tol) {
  int n = 0;
  for (const Block& B : blocks) n += Beyond(MaxD(In(K), In(U), In(S), B), tol) ? 1 : 0;
  return n;
}

BlockAnalysis Analyze(MatrixView K_view, MatrixView U_view, const Scales& S_matrix,
                      const std::vector<Block>& blocks, const std::string& matrix, double tol) {
  const ColumnMajorEntries K = In(K_view), U = In(U_view), S = In(S_matrix);
  BlockAnalysis out;
  std::vector<double> before(blocks.size());
  std::vector<bool> open(blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    before[b] = MaxD(K, U, S, blocks[b]);
    open[b] = Beyond(before[b], tol);
    if (open[b]) {
      ++out.mismatched;
      out.mismatch_sum += before[b];
    }
  }
  const auto finding = [&](std::size_t b, const std::string& kind, double f, double residual) {
    out.findings.push_back(
        {matrix, {blocks[b].row}, {blocks[b].col}, kind, f, before[b], residual});
    open[b] = false;
  };
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    if (!open[b]) continue;
    const Block& B = blocks[b];
    // The fixed kinds (missing, sign, swap, transpose): the one with the smallest residual
    // within tolerance, the first in that order on a tie (a block whose reference is itself
    // nearly zero is fitted by "missing" and by "sign" alike; the smaller residual says which
    // it is).
    std::string kind;
    double best = tol, factor = 1.0;
    std::size_t partner = b;
    const auto consider = [&](const std::string& k, double f, double r, std::size_t c) {
      if (r <= tol && (kind.empty() || r < best)) {
        kind = k;
        best = r;
        factor = f;
        partner = c;
      }
    };
    // Missing: exactly zero (terms never formed are never written as anything else; a block
    // merely far smaller than the reference is a scale, e.g. a density used as a variance).
    if (U_view.block(B.r0, B.c0, 3, 3).isZero(0.0))
      consider("missing", 0.0, Residual(K, U, S, B, 0.0, Same), b);
    consider("sign", -1.0, Residual(K, U, S, B, -1.0, Same), b);
    for (std::size_t c = b + 1; c < blocks.size(); ++c) {
      if (!open[c]) continue;
      const Block& C = blocks[c];
      const double r_bc = Residual(K, U, S, B, 1.0, [&](Eigen::Index i, Eigen::Index j) {
        return std::pair{C.r0 + (i - B.r0), C.c0 + (j - B.c0)};
      });
      const double r_cb = Residual(K, U, S, C, 1.0, [&](Eigen::Index i, Eigen::Index j) {
        return std::pair{B.r0 + (i - C.r0), B.c0 + (j - C.c0)};
      });
      consider("swap", 1.0, std::max(r_bc, r_cb), c);
    }
    consider("transpose", 1.0,
             Residual(K, U, S, B, 1.0,
                      [&](Eigen::Index i, Eigen::Index j) {
                        return std::pair{B.r0 + (j - B.c0), B.c0 + (i - B.r0)};
                      }),
             b);
    if (kind == "swap") {
      const Block& C = blocks[partner];
      out.findings.push_back({matrix,
                              {B.row, C.row},
                              {B.col, C.col},
                              "swap",
                              1.0,
                              std::max(before[b], before[partner]),
                              best});
      open[b] = open[partner] = false;
      continue;
    }
    if (!kind.empty()) {
      finding(b, kind, factor, best);
      continue;
    }
    const double f = FittedScale(K, U, S, B);
    if (f != 0.0)
      if (const double r = Residual(K, U, S, B, f, Same); r <= tol) {
        finding(b, "scale", f, r);
        continue;
      }
    out.unexplained.push_back({matrix, {B.row}, {B.col}, before[b]});
    open[b] = false;
  }
  return out;
}

std::string Num3(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

}  // namespace

BlockAnalysis AnalyzeJacobianBlocks(MatrixView K, MatrixView U,
                                    const std::vector<std::string>& row_labels,
                                    const std::vector<std::string>& col_labels, double tol) {
  return Analyze(K, U, JacobianScales(K), JacobianBlocks(&row_labels, &col_labels), "J_bias", tol);
}

BlockAnalysis AnalyzeCovarianceBlocks(MatrixView K, MatrixView U,
                                      const std::vector<std::string>& labels, double tol) {
  return Analyze(K, U, CovarianceScales(K), CovarianceBlocks(labels), "cov", tol);
}

int JacobianBlocksBeyond(MatrixView K, MatrixView U, double tol) {
  return CountBeyond(K, U, JacobianScales(K), JacobianBlocks(nullptr, nullptr), tol);
}

int CovarianceBlocksBeyond(const ReorderedCovarianceDiffs::BlockMaxD& block_max_d, double tol) {
  int n = 0;
  for (std::size_t a = 0; a < 5; ++a)
    for (std::size_t b = a; b < 5; ++b) n += Beyond(block_max_d[a][b], tol) ? 1 : 0;
  return n;
}

std::string FactorWords(double factor, double dt) {
  const double a = std::abs(factor);
  const std::string sign = factor < 0.0 ? "-" : "";
  const std::pair<double, const char*> named[] = {{2.0, "2"},
                                                  {0.5, "1/2"},
                                                  {4.0, "4"},
                                                  {0.25, "1/4"},
                                                  {1.0 / dt, "1/dt"},
                                                  {dt, "dt"},
                                                  {1.0 / (dt * dt), "1/dt^2"},
                                                  {dt * dt, "dt^2"}};
  // 1 %: the tolerance a scale finding was fitted to.
  if (dt > 0.0)
    for (const auto& [value, words] : named)
      if (std::abs(a / value - 1.0) <= 1e-2) return sign + words;
  return Num3(factor);
}

std::string FindingWords(const BlockFinding& f, double dt) {
  const std::string where = f.matrix + " block (rows " + f.rows[0] + ", cols " + f.cols[0] + ")";
  // A residual below 1e-9 is round-off (explain.cpp's tie tolerance): said as such, so the
  // same numbers by two routes (a case and a pipeline) read the same.
  const std::string residual = f.residual < 1e-9 ? std::string("< 1e-9") : Num3(f.residual);
  const std::string d = " (max d " + Num3(f.max_d) + ", " + residual + " once undone)";
  if (f.kind == "missing")
    return where + " is zero where the reference is not: terms never formed" + d;
  if (f.kind == "sign") return where + " has the opposite sign" + d;
  if (f.kind == "transpose") return where + " is transposed" + d;
  if (f.kind == "swap")
    return where + " and " + f.matrix + " block (rows " + f.rows[1] + ", cols " + f.cols[1] +
           ") are swapped" + d;
  std::string w = FactorWords(f.factor, dt);
  if (w.find("dt") != std::string::npos)
    w += " (dt = " + Num3(dt) + " s, the median sample period)";
  return where + " is scaled by " + w + d;
}

}  // namespace imuconv::check
