// Block-level findings: where no global explanation (chart, block order, column order, sign)
// fits a user's J_bias or covariance, what is wrong block by block. The reference K (the
// numbers the nearest explanation predicts, arranged as the user's) and the user's U are cut
// into 3x3 blocks (J_bias: its theta, p, v row blocks x its two bias column blocks; the
// covariance: each block on and above the diagonal, the one below being its transpose), and
// each block beyond tolerance is explained, when one of these fits within tolerance, by
//   missing    U's block is exactly zero where K's is not (terms never formed),
//   sign       U = -K,
//   swap       U's block is K's block at another position, and that one U's is this K's,
//   transpose  U = K^T (a 3x3 block stored by columns),
//   scale      U = f K with f fitted (least squares in the part's own metric): x2, x4, 1/dt ...
// the four fixed kinds first (the one with the smallest residual, the first listed on a tie: a
// sign is also a scale by -1, a zero block a scale by 0), a fitted scale only when none of
// them fits. A block none of them fits is "unexplained" and reported with its max d.
//
// Every residual is the part's own difference (difference.h) of U from the corrected
// reference, divided by |f| for a scale: the relative difference above 1e-4 of K's largest
// entry for J_bias, the correlation scale sqrt(K_ii K_jj) of the source entry for the
// covariance. Dividing by |f| makes "U = f K to 1 %" read as 1e-2 whatever f is, so a scale
// finding of x78 is judged as strictly as one of x2.
#pragma once

#include <string>
#include <vector>

#include "imuconv/check/difference.h"

namespace imuconv::check {

/// One block explained. `rows` and `cols` are block labels: one of each for a block; for a
/// swap two of each, block (rows[0], cols[0]) exchanged with block (rows[1], cols[1]).
struct BlockFinding {
  std::string matrix;  // "J_bias" or "cov"
  std::vector<std::string> rows, cols;
  std::string kind;       // "missing", "sign", "swap", "transpose", "scale"
  double factor = 1.0;    // scale: U = factor K; sign: -1; missing: 0; swap, transpose: 1
  double max_d = 0.0;     // the block's max d as the numbers are
  double residual = 0.0;  // its max d once the finding is undone (<= the tolerance)
};

/// A block beyond tolerance that no kind explains.
struct UnexplainedBlock {
  std::string matrix;
  std::vector<std::string> rows, cols;
  double max_d = 0.0;
};

struct BlockAnalysis {
  std::vector<BlockFinding> findings;
  std::vector<UnexplainedBlock> unexplained;
  /// The blocks beyond tolerance (a swap's two count as two), and the sum of their max d:
  /// what "fewest and smallest findings" compares (explain.h).
  int mismatched = 0;
  double mismatch_sum = 0.0;
  bool empty() const { return findings.empty() && unexplained.empty(); }
};

/// J_bias (9x6): `row_labels` the three row blocks, `col_labels` the two column blocks.
BlockAnalysis AnalyzeJacobianBlocks(MatrixView K, MatrixView U,
                                    const std::vector<std::string>& row_labels,
                                    const std::vector<std::string>& col_labels, double tol);

/// The covariance (15x15), `labels` its five blocks in order.
BlockAnalysis AnalyzeCovarianceBlocks(MatrixView K, MatrixView U,
                                      const std::vector<std::string>& labels, double tol);

/// The blocks beyond tolerance before any finding explains them: the `mismatched` of
/// AnalyzeJacobianBlocks and AnalyzeCovarianceBlocks, without looking for findings. An
/// analysis counts each such block once or twice (explain.h), so this bounds its count of
/// corrections from below: what lets the search analyze only the candidates that can still win
/// (explain.cpp). J_bias: computed by the analysis's own code. The covariance: from the search's
/// block maxima (ReorderedCovarianceDiffs::BlockMaxima, difference.h), each block's max of the
/// same per-entry d, |K_ij - U_ij| / sqrt|K_ii K_jj| (the largest variance where that is 0),
/// so the same count when the reference is finite; the blocks on and above the diagonal, as
/// the analysis takes them.
int JacobianBlocksBeyond(MatrixView K, MatrixView U, double tol);
int CovarianceBlocksBeyond(const ReorderedCovarianceDiffs::BlockMaxD& block_max_d, double tol);

/// A factor in words when it is (to 1 %) a simple one: "2", "1/2", "4", "1/4", "1/dt", "dt",
/// "1/dt^2", "dt^2" with `dt` the sample period; else its value to three digits.
std::string FactorWords(double factor, double dt);

/// One finding in words, e.g. "J_bias block (rows theta, cols bg) has the opposite sign".
std::string FindingWords(const BlockFinding& f, double dt);

}  // namespace imuconv::check
