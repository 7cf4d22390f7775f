// The entrywise difference d of the note (J. Huai, "IMU Propagation as Preintegration"), made
// scale-aware as the project's tests make it (tests/support/scale_aware.h), with its maximum
// and mean over the entries:
//  - a covariance on the correlation scale, |K_ij - U_ij| / sqrt(K_ii K_jj): a correlation
//    error, the same for a 1e-10 bias variance and a 1e2 position variance (the note's plain
//    d would not look at the bias blocks at all, whose entries are below its 1e-4 threshold);
//  - any other matrix or vector relative to the larger of |K_ij| and 1e-4 of its largest
//    entry (the note's 1e-4 threshold, taken relative to the matrix's scale).
// K is the reference (the numbers an explanation predicts), U the user's numbers. A
// non-finite entry is an infinite difference.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

namespace imuconv::check {

/// A matrix read in place: a fixed-size one (Mat15, Mat96, a vector) binds without a copy,
/// which matters in the search, which compares thousands of candidates per measurement.
using MatrixView = const Eigen::Ref<const Eigen::MatrixXd>&;

/// A matrix's column-major entries read in place: Eigen's operator() on a view is a call per
/// entry in the sanitized build's -O1, where the search spent most of its time in it.
struct ColumnMajorEntries {
  const double* data;
  Eigen::Index stride;
  ColumnMajorEntries(const double* d, Eigen::Index outer_stride) : data(d), stride(outer_stride) {}
  explicit ColumnMajorEntries(MatrixView m) : ColumnMajorEntries(m.data(), m.outerStride()) {}
  double operator()(Eigen::Index i, Eigen::Index j) const { return data[i + j * stride]; }
};

struct EntryDiff {
  double max = 0.0, mean = 0.0;
};

/// Two differences of a covariance `user` from a reference `ref` taken under symmetric
/// reorderings of ref's rows and columns (imuconv check's search over the 120 orders of five
/// blocks). The reference's scales sqrt|K_ii K_jj| and correlations, and the user's
/// correlations, are computed once; each reordering reads them through its index map:
///  - CorrelationScale: |K_ij - U_ij| / sqrt(K_ii K_jj), max and mean; a zero reference
///    variance (a state no noise reaches) is judged against the largest one;
///  - CorrelationStructure: max |rho_K - rho_U| of the two correlation matrices (rho_ij =
///    C_ij / sqrt(C_ii C_jj); 0 where a variance is not positive): the covariance's structure
///    with each variance's scale taken out. What ranks covariance explanations when none is
///    within tolerance: a covariance scaled (x2), or with each noise source scaled by its own
///    factor, keeps much of its correlation structure, while the max of CorrelationScale
///    saturates near 1 for every candidate once the user's variances are far smaller than
///    the reference's.
class ReorderedCovarianceDiffs {
 public:
  ReorderedCovarianceDiffs(MatrixView ref, MatrixView user);
  /// `from[i]`: the row and column of `ref` that row and column i of the reordering take
  /// (ref.rows() entries).
  EntryDiff CorrelationScale(const Eigen::Index* from) const;
  /// The max of CorrelationScale's d over each 3x3 block of a 15x15 reordering: [a][b] is
  /// the block of rows 3a..3a+2 and columns 3b..3b+2 (NaN counted as infinite).
  using BlockMaxD = std::array<std::array<double, 5>, 5>;
  /// For a 15x15 reordering that moves whole 3-blocks (`from` maps block b's three rows to
  /// those of one block of `ref`, in order, as ReorderedIndices does): each block's max d,
  /// from a table of each user block's max d against each reference block, made once (625
  /// blocks of 9 entries, against 120 orders of 225 entries). A max does not depend on the
  /// order its entries are taken in, so their max is CorrelationScale's to the bit; its mean,
  /// a sum in entry order, is not given.
  BlockMaxD BlockMaxima(const Eigen::Index* from) const;
  /// Whether every entry of the reference is finite (a NaN makes its largest variance depend
  /// on the order of the diagonal, so a reordered copy's may differ).
  bool ReferenceFinite() const { return ref_finite_; }
  double CorrelationStructure(const Eigen::Index* from) const;

 private:
  Eigen::MatrixXd ref_, user_, scale_, rho_ref_, rho_user_;
  double largest_ = 0.0;
  bool ref_finite_ = true;
  /// [a][b][pa][pb]: the max d of the user's block (a, b) against the reference's (pa, pb);
  /// empty unless 15x15.
  std::vector<double> block_table_;
};

/// Relative difference above the floor 1e-4 x max|ref|.
EntryDiff RelativeAboveFloorDiff(MatrixView ref, MatrixView user);

// The same differences entry by entry (what a heatmap draws; ReorderedCovarianceDiffs's
// CorrelationScale and RelativeAboveFloorDiff are their max and mean), and the note's d exactly as
// it defines it: |r - e| / |r| where |r| > 1e-4, else |r - e|, with an absolute threshold (the
// note's Figures 1 and 2). A non-finite entry of `user`, or a NaN difference, is an infinite
// difference.
Eigen::MatrixXd CorrelationScaleEntries(MatrixView ref, MatrixView user);
Eigen::MatrixXd RelativeAboveFloorEntries(MatrixView ref, MatrixView user);
Eigen::MatrixXd NoteEntries(MatrixView ref, MatrixView user);

/// Max and mean of a matrix of entrywise differences (NaN counts as infinite).
EntryDiff Summarize(MatrixView entries);

}  // namespace imuconv::check
