// Built-in pieces of the registry: the increment reference chart as a convention.
#pragma once

#include "imuconv/plugin/convention.h"

namespace imuconv::detail {

/// `preint_reference`: dR = dR^ Exp(dtheta), dp, dv, Delta b additive; [theta, p, v, bg, ba].
class PreintReferenceConvention final : public plugin::IncrementChart<kPreintReferenceOrder, 1> {
 public:
  const char* id() const noexcept override { return ReferenceChart<PreintIncrement>::id; }
  void retract(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) const noexcept override;
  void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept override;
  bool J_ref_this(const PreintIncrement&, Mat15& J) const noexcept override { return RefThis(J, {}); }
  bool J_this_ref(const PreintIncrement&, Mat15& J) const noexcept override { return ThisRef(J, {}); }
};

}  // namespace imuconv::detail
