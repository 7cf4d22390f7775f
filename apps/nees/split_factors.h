// The two noise factors of imuconv nees: one scale on the gyro densities, one on the
// accelerometer densities, fitted block by block (docs/nees.md, "Two factors").
//
// One factor on all four densities mixes the two sensors: on EuRoC V1_01 the theta block alone
// wants about 7, the p and v blocks about 10 to 11. The covariance recursion
// P+ = F P F^T + G Q G^T is linear in Q (F does not depend on the noise; the note's
// eq. (cov-recursion)), and Q is block diagonal in the four densities, so from a zero start
// covariance each window's covariance splits exactly into a gyro part and an accelerometer part,
// each scaling with the square of its own densities' scale:
//   P(k_g, k_a) = k_g^2 P_g + k_a^2 P_a,
// P_g propagated with the gyro densities alone (white noise and random walk), P_a with the
// accelerometer's alone. The rotation error is driven by the gyro only (the accelerometer enters
// v and p, never theta), so theta's block of P_a is zero and k_gyro is fitted on theta alone;
// then k_accel on the v block with k_gyro fixed.
#pragma once

#include <vector>

#include "imuconv/types.h"

namespace imuconv::nees {

/// The median of chi-square with 3 dof, one block's NEES.
double ChiSquare3Median();

/// The NEES of the 3-block starting at `offset` (0 p, 3 theta, 6 v) of `error` under `cov`'s
/// diagonal 3x3 block; +infinity when that block is not positive definite.
double BlockNees(const Vec9& error, const Mat9& cov, int offset);

/// k_gyro: the scale on the gyro densities that puts the median over windows of theta's NEES
/// (3 dof) on chi-square(3)'s median. theta's NEES under k_g^2 P_g is NEES(1) / k_g^2, so
/// k_g = sqrt(median NEES_theta(1) / chi2_3 median), in closed form. NaN when a window's
/// theta block of P_g is not positive definite (gyro densities zero).
double FitGyroFactor(const std::vector<Vec9>& error, const std::vector<Mat9>& cov_gyro);

/// k_accel: with the gyro part scaled by k_gyro, the scale on the accelerometer densities that
/// puts the median of the v block's NEES on chi-square(3)'s median, by bisection on log k_a
/// (each window's v NEES, hence their median, decreases as k_a grows). 0 when the gyro part
/// alone already brings the median below the target (k_a = 1e-12 is the smallest tried); NaN
/// when no k_a up to 1e12 reaches it (accelerometer densities zero) or k_gyro is NaN.
double FitAccelFactor(const std::vector<Vec9>& error, const std::vector<Mat9>& cov_gyro,
                      const std::vector<Mat9>& cov_accel, double k_gyro);

/// k_g^2 P_g + k_a^2 P_a.
Mat9 ScaledCovariance(const Mat9& cov_gyro, const Mat9& cov_accel, double k_gyro, double k_accel);

}  // namespace imuconv::nees
