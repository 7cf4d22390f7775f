// ErrorState: one perturbation (error-state) convention on the 15-dof IMU state.
//
// A convention is a chart: retract(x, d) applies the 15-vector d to the estimate x and
// local(x, y) recovers d, with local(x, retract(x, d)) = d. The order of the five
// 3-blocks is part of the convention and is declared by labels() (paper, section 2.1:
// x = x^ [+]^p dx^p).
//
// Every state convention is related to the others through the reference convention
// `left` (p = p^ + dp, R = Exp(dtheta) R^, v = v^ + dv, b = b^ + db; order
// [p, theta, v, bg, ba]). A convention may give the Jacobians to and from it
// analytically; the registry checks them against central differences when it loads
// the plugin, and derives them numerically when they are absent.
#pragma once

#include <array>

#include "imuconv/types.h"

namespace imuconv {

/// Labels of the five 3-blocks, e.g. {"theta","p","v","ba","bg"}. States use
/// "p","theta","v","bg","ba"; preintegrated increments use the same labels for
/// dp, dtheta, dv, dbg, dba.
using BlockLabels = std::array<const char*, 5>;

class ErrorState {
 public:
  virtual ~ErrorState() = default;
  virtual const char* id() const noexcept = 0;
  virtual BlockLabels labels() const noexcept = 0;
  /// y = x [+] d.
  virtual void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept = 0;
  /// d = y [-] x, the inverse of retract.
  virtual void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept = 0;
  /// J = d local_left(x, retract_this(x, d)) / d d at d = 0. Return false if not given.
  virtual bool jacobian_to_reference(const ImuState& /*x*/, Mat15& /*J*/) const noexcept { return false; }
  /// J = d local_this(x, retract_left(x, e)) / d e at e = 0. Return false if not given.
  virtual bool jacobian_from_reference(const ImuState& /*x*/, Mat15& /*J*/) const noexcept { return false; }
};

/// A perturbation convention on the preintegrated increment (dR, dp, dv, Delta b)
/// (paper, eq. preint-error-dr..db and the "GTSAM peculiarities" paragraph).
///
/// The reference chart for increments is `preint_reference`:
///   dR = dR^ Exp(dtheta), dp = dp^ + dp, dv = dv^ + dv, Delta b = Delta b^ + db,
///   order [theta, p, v, bg, ba].
///
/// A preintegration module may report its bias Jacobian in one chart and its covariance
/// in another (GTSAM's ManifoldPreintegration does): bias_jacobian_chart() names the
/// convention whose chart the bias Jacobian of a measurement "in this convention" uses;
/// it defaults to the convention itself.
class PreintConvention {
 public:
  virtual ~PreintConvention() = default;
  virtual const char* id() const noexcept = 0;
  virtual BlockLabels labels() const noexcept = 0;
  virtual void retract(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) const noexcept = 0;
  virtual void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept = 0;
  virtual const char* bias_jacobian_chart() const noexcept { return id(); }
  /// J = d local_reference(x, retract_this(x, d)) / d d at d = 0.
  virtual bool jacobian_to_reference(const PreintIncrement& /*x*/, Mat15& /*J*/) const noexcept { return false; }
  /// J = d local_this(x, retract_reference(x, e)) / d e at e = 0.
  virtual bool jacobian_from_reference(const PreintIncrement& /*x*/, Mat15& /*J*/) const noexcept { return false; }
};

}  // namespace imuconv
