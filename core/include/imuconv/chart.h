// Chart<Value>: one perturbation convention on a value (J. Huai, "IMU Propagation as
// Preintegration", section 2.1), written once for both kinds:
//   StateConvention     = Chart<ImuState>          (error states; reference chart `left`)
//   IncrementConvention = Chart<PreintIncrement>   (preintegrated increments; reference
//                                                   chart `preint_reference`)
//
// A convention is a chart: retract(x, d) applies the 15-vector d to the estimate x and
// local(x, y) recovers d, with local(x, retract(x, d)) = d. The order of the five 3-blocks is
// part of the convention and is declared once by order(). Every convention is related to the
// others through its kind's reference chart (reference_charts.h). It may give the Jacobians
// to and from it analytically (J_ref_this, J_this_ref); the registry checks them against
// Ridders' differences when it loads the plugin and derives them numerically when they are
// absent. Jacobians are named J_out_in: J_ref_this maps this chart's perturbation to the
// reference chart's.
#pragma once

#include "imuconv/block_order.h"
#include "imuconv/types.h"

namespace imuconv {

template <class Value>
class Chart {
 public:
  using value_type = Value;

  virtual ~Chart() = default;
  virtual const char* id() const noexcept = 0;
  /// The order of the five 3-blocks of d.
  virtual BlockOrder order() const noexcept = 0;
  /// y = x [+] d.
  virtual void retract(const Value& x, const Vec15& d, Value& y) const noexcept = 0;
  /// d = y [-] x, the inverse of retract.
  virtual void local(const Value& x, const Value& y, Vec15& d) const noexcept = 0;
  /// J_ref_this = d local_ref(x, retract_this(x, d)) / d d at d = 0. Return false if not given.
  virtual bool J_ref_this(const Value& /*x*/, Mat15& /*J*/) const noexcept { return false; }
  /// J_this_ref = d local_this(x, retract_ref(x, e)) / d e at e = 0. Return false if not given.
  virtual bool J_this_ref(const Value& /*x*/, Mat15& /*J*/) const noexcept { return false; }
  /// The convention whose chart a measurement's bias Jacobian "in this convention" uses; a
  /// preintegration module may report its bias Jacobian in one chart and its covariance in
  /// another (GTSAM's ManifoldPreintegration does). Defaults to the convention itself.
  virtual const char* jacobian_convention() const noexcept { return id(); }

  /// order() as labels, e.g. {"theta","p","v","ba","bg"}.
  BlockLabels labels() const noexcept { return order().labels(); }
};

using StateConvention = Chart<ImuState>;
using IncrementConvention = Chart<PreintIncrement>;

}  // namespace imuconv
