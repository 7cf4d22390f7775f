// The search for what explains a user's numbers: the scheme, the covariance's convention and
// block order, and the bias Jacobian's row chart, column order and sign, each scored by the
// scale-aware entrywise difference (difference.h) of the user's numbers from what that
// explanation predicts (candidates.h).
//
// The covariance and the bias Jacobian are explained independently given the scheme (no
// candidate of one changes the other's numbers), so the search is their sum, not their
// product: per scheme 7 conventions x 120 block orders for the covariance, 7 charts x 2 column
// orders x 2 signs for the Jacobian. What keeps it cheap without changing any result
// (explain.cpp): each convention's block differences are tabled once (difference.h,
// BlockMaxima) and the block analysis runs only on candidates that can still win.
#pragma once

#include <string>
#include <vector>

#include "imuconv/check/block_findings.h"
#include "imuconv/check/candidates.h"
#include "imuconv/check/difference.h"

namespace imuconv::check {

/// How far a user's numbers may be from an explanation and still be explained by it, on the
/// max of each difference (the values and why they are right: verdict.cpp).
struct Tolerances {
  double delta = 0.0, J_bias = 0.0, cov = 0.0;
};

/// A covariance explanation and a J_bias explanation, without their differences: what
/// `Equivalents` lists.
struct CovarianceChoice {
  std::string convention;
  std::vector<std::string> blocks;
  bool operator==(const CovarianceChoice& o) const {
    return convention == o.convention && blocks == o.blocks;
  }
};
struct JacobianChoice {
  std::string chart;
  std::vector<std::string> columns;
  int sign = 1;
  bool operator==(const JacobianChoice& o) const {
    return chart == o.chart && columns == o.columns && sign == o.sign;
  }
};

/// The explanations other than the one picked that the search cannot tell from it: their
/// differences (and block findings) are the pick's within the tie tolerance (explain.cpp), so
/// they are the same numbers. The pick among them is the first in the search order.
struct Equivalents {
  std::vector<std::string> schemes;
  std::vector<CovarianceChoice> cov;
  std::vector<JacobianChoice> J_bias;
  bool empty() const { return schemes.empty() && cov.empty() && J_bias.empty(); }
};

/// One explanation of a measurement and the differences under it.
struct Explanation {
  std::string scheme;
  std::string convention;           // of the covariance
  std::vector<std::string> blocks;  // the covariance's block order
  std::string jacobian_convention;  // J_bias's row chart
  std::vector<std::string> J_bias_columns;
  int J_bias_sign = 1;
  EntryDiff delta, J_bias, cov;
  /// What is wrong block by block when a part is beyond tolerance (block_findings.h); empty
  /// for a part within it.
  BlockAnalysis J_bias_blocks, cov_blocks;
  Equivalents equivalent;
};

/// What a search may choose; an empty field (or no sign) is free.
struct Constraints {
  std::string convention;
  std::vector<std::string> blocks;
  std::string jacobian_convention;
  std::vector<std::string> J_bias_columns;
  int J_bias_sign = 0;  // 0: free
};

/// The user's numbers as written.
struct UserNumbers {
  Eigen::Matrix<double, 15, 1> delta;
  Mat96 J_bias;
  Mat15 cov;
};

/// The best explanation under `c`. Per scheme and part (covariance, J_bias): the candidate
/// with the smallest max difference, then mean; when none is within tolerance, the one that
/// needs the fewest corrections block by block (block_findings.h; a 3x3 block beyond tolerance
/// counts one when a block finding explains it, two when none does), then the fewest blocks
/// unexplained, the smallest sum of their max d (then, for the covariance, the nearest
/// correlation structure), then max and mean d. Across schemes: the fewest parts (increment,
/// J_bias, covariance) beyond tolerance, then the smallest sum of the parts within tolerance
/// (each divided by its tolerance), the fewest blocks beyond tolerance and unexplained, then
/// the smallest sum of the parts beyond. Every comparison treats values within the tie
/// tolerance (explain.cpp) as equal, and ties keep the first found: what `prefer` names (the
/// declaration) first, then the registry's order, a chart's own block order first, [bg, ba]
/// before [ba, bg], + before -. The tied others are the explanation's `equivalent`.
Explanation Explain(const std::vector<SchemeCandidates>& schemes, const UserNumbers& user,
                    const Constraints& c, const Tolerances& tol, const Constraints& prefer = {});

/// The worst part of an explanation relative to its tolerance (<= 1: within tolerance).
double Score(const Explanation& e, const Tolerances& tol);

}  // namespace imuconv::check
