// Numerical Jacobians of maps R^15 -> R^15 at 0, used to derive conversion Jacobians for
// conventions that give none and to check the analytic ones.
#pragma once

#include <functional>

#include "imuconv/export.h"
#include "imuconv/types.h"

namespace imuconv {

using Map15 = std::function<void(const Vec15& in, Vec15& out)>;

/// Central difference with step h: J(:,i) = (f(h e_i) - f(-h e_i)) / 2h. Error O(h^2).
IMUCONV_API Mat15 CentralJacobian(const Map15& f, double h = 1e-6);

/// Ridders' extrapolation of central differences (Numerical Recipes, dfridr), column by
/// column, starting at step h0 and shrinking by 1.4. Reaches ~1e-12 relative on smooth maps.
IMUCONV_API Mat15 RiddersJacobian(const Map15& f, double h0 = 0.05);

}  // namespace imuconv
