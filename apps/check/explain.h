// The search for what explains a user's numbers: the scheme, the covariance's convention and
// block order, and the bias Jacobian's row chart, column order and sign, each scored by the
// scale-aware entrywise difference (difference.h) of the user's numbers from what that
// explanation predicts (candidates.h).
//
// The covariance and the bias Jacobian are explained independently given the scheme (no
// candidate of one changes the other's numbers), so the search is their sum, not their
// product: per scheme 7 conventions x 120 block orders for the covariance, 7 charts x 2 column
// orders x 2 signs for the Jacobian; about 6e5 entry comparisons per measurement in all.
#pragma once

#include <string>
#include <vector>

#include "candidates.h"
#include "difference.h"

namespace imuconv::check {

/// How far a user's numbers may be from an explanation and still be explained by it, on the
/// max of each difference (the values and why they are right: verdict.cpp).
struct Tolerances {
  double delta = 0.0, J_bias = 0.0, cov = 0.0;
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

/// The best explanation under `c`: per scheme the covariance candidate with the smallest max
/// difference (then mean) and likewise the Jacobian, and the scheme with the fewest parts
/// (increment, J_bias, covariance) beyond tolerance, then the smallest sum of the parts within
/// tolerance (each divided by its tolerance), then of those beyond. Ties keep the first found:
/// what `prefer` names (the declaration) first, then the registry's order, a chart's own block
/// order first.
Explanation Explain(const std::vector<SchemeCandidates>& schemes, const UserNumbers& user, const Constraints& c,
                    const Tolerances& tol, const Constraints& prefer = {});

/// The worst part of an explanation relative to its tolerance (<= 1: within tolerance).
double Score(const Explanation& e, const Tolerances& tol);

}  // namespace imuconv::check
