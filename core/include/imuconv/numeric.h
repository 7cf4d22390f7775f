// Numerical Jacobians of maps R^15 -> R^15 at 0, used to derive conversion Jacobians for
// conventions that give none and to check the analytic ones.
#pragma once

#include <functional>
#include <string>

#include "imuconv/export.h"
#include "imuconv/types.h"

namespace imuconv {

using Map15 = std::function<void(const Vec15& in, Vec15& out)>;

/// Central difference with step h: J(:,i) = (f(h e_i) - f(-h e_i)) / 2h. Error O(h^2).
IMUCONV_API Mat15 CentralJacobian(const Map15& f, double h = 1e-6);

/// Ridders' extrapolation of central differences (Numerical Recipes, dfridr), column by
/// column, starting at step h0 and shrinking by 1.4. Reaches ~1e-12 relative on smooth maps.
IMUCONV_API Mat15 RiddersJacobian(const Map15& f, double h0 = 0.05);

/// Relative tolerance of CovarianceProblem, on the correlation scale (entries divided by
/// sqrt(C_ii C_jj)). Round-off in a covariance computed and written in double precision is
/// about 1e-15 on that scale, and a matrix assembled as J S J^T with heavy cancellation stays
/// well under 1e-12; a real defect (a sign flip, a transposed block, a variance used where a
/// standard deviation was meant off the diagonal) is of order 1e-3 or more.
constexpr double kCovarianceTol = 1e-9;

/// What is wrong with C as a covariance, or "" when nothing is: not square, a non-finite
/// entry, a negative variance, asymmetry beyond `tol` on the correlation scale, or a
/// smallest eigenvalue of the correlation matrix below -tol (not positive semi-definite).
/// The message names the entry (0-based row, column) or gives the smallest eigenvalue of C
/// itself and of its correlation matrix. Nothing is repaired.
IMUCONV_API std::string CovarianceProblem(const Eigen::MatrixXd& C, double tol = kCovarianceTol);

}  // namespace imuconv
