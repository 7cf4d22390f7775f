// What each explanation predicts a user's numbers to be, from one reference (Preintegrated,
// in the reference charts) of one scheme:
//   - the covariance in every registered increment convention, in that convention's block
//     order (Express, bridge.h), and any reordering of its five 3-blocks;
//   - the bias Jacobian with its rows in every registered increment convention (the rows of
//     that chart's theta, p, v blocks, in its order), columns [bg, ba] or [ba, bg], and either
//     sign: + is d(increment)/d(bias estimate), what imuconv and GTSAM store; - is the
//     derivative with respect to a bias correction (b_hat - b), which some code stores.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "imuconv/bridge.h"

namespace imuconv::check {

/// The increment as 15 numbers: the rotation matrix row by row, dp, dv (compared entrywise:
/// the increment carries no chart).
Eigen::Matrix<double, 15, 1> IncrementEntries(const PreintIncrement& d);

struct CovarianceCandidate {
  std::string convention;
  std::vector<std::string> labels;  // the convention's own block order
  Mat15 cov;                        // in that order
};

struct JacobianCandidate {
  std::string chart;
  std::vector<std::string> rows;  // the chart's theta, p, v blocks in its order
  Mat96 J_bg_ba;  // rows: the chart's theta, p, v blocks in its order; columns [bg, ba]
};

/// Every candidate of one scheme's reference.
struct SchemeCandidates {
  std::string scheme;
  Eigen::Matrix<double, 15, 1> delta;
  std::vector<CovarianceCandidate> covariances;  // one per registered increment convention
  std::vector<JacobianCandidate> jacobians;      // one per registered increment convention
};

SchemeCandidates MakeCandidates(const Registry& reg, const std::string& scheme,
                                const Preintegrated& ref);

/// The candidate's covariance with its blocks in `order` (an ordering of its labels).
Mat15 Reordered(const CovarianceCandidate& c, const std::vector<std::string>& order);

/// Row (and column) i of Reordered(c, order) is row (and column) ReorderedIndices(c, order)[i] of
/// c.cov.
std::array<Eigen::Index, 15> ReorderedIndices(const CovarianceCandidate& c,
                                              const std::vector<std::string>& order);

/// The candidate's bias Jacobian with columns in `columns` ({"bg", "ba"} or {"ba", "bg"}) and
/// multiplied by `sign`.
Mat96 Arranged(const JacobianCandidate& c, const std::vector<std::string>& columns, int sign);

}  // namespace imuconv::check
