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

namespace imuconv::check {

struct EntryDiff {
  double max = 0.0, mean = 0.0;
};

/// Correlation-scale difference of a covariance `user` from the reference covariance `ref`.
/// A zero reference variance (a state no noise reaches) is judged against the largest one.
EntryDiff CorrelationScaleDiff(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user);

/// Max |rho_K - rho_U| of the two correlation matrices (rho_ij = C_ij / sqrt(C_ii C_jj); 0
/// where a variance is not positive): the covariance's structure with each variance's scale
/// taken out. What ranks covariance explanations when none is within tolerance: a
/// covariance scaled (x2), or with each noise source scaled by its own factor, keeps much of
/// its correlation structure, while the max of CorrelationScaleDiff saturates near 1 for
/// every candidate once the user's variances are far smaller than the reference's.
double CorrelationStructureDiff(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user);

/// Relative difference above the floor 1e-4 x max|ref|.
EntryDiff RelativeAboveFloorDiff(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user);

// The same differences entry by entry (what a heatmap draws; the EntryDiff functions above
// are their max and mean), and the note's d exactly as it defines it: |r - e| / |r| where
// |r| > 1e-4, else |r - e|, with an absolute threshold (the note's Figures 1 and 2). A
// non-finite entry of `user`, or a NaN difference, is an infinite difference.
Eigen::MatrixXd CorrelationScaleEntries(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user);
Eigen::MatrixXd RelativeAboveFloorEntries(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user);
Eigen::MatrixXd NoteEntries(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& user);

/// Max and mean of a matrix of entrywise differences (NaN counts as infinite).
EntryDiff Summarize(const Eigen::MatrixXd& entries);

}  // namespace imuconv::check
