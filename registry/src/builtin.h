// Built-in pieces of the registry: the increment reference chart as a convention.
#pragma once

#include "imuconv/error_state.h"

namespace imuconv::detail {

/// `preint_reference`: dR = dR^ Exp(dtheta), dp, dv, Delta b additive; [theta, p, v, bg, ba].
class PreintReferenceConvention final : public PreintConvention {
 public:
  const char* id() const noexcept override { return "preint_reference"; }
  BlockLabels labels() const noexcept override { return {"theta", "p", "v", "bg", "ba"}; }
  void retract(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) const noexcept override;
  void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept override;
  bool jacobian_to_reference(const PreintIncrement&, Mat15& J) const noexcept override {
    J.setIdentity();
    return true;
  }
  bool jacobian_from_reference(const PreintIncrement&, Mat15& J) const noexcept override {
    J.setIdentity();
    return true;
  }
};

}  // namespace imuconv::detail
