// Built-in pieces of the registry: the increment reference chart as a convention.
#pragma once

#include "imuconv/plugin/convention.h"

namespace imuconv::detail {

/// `preint_reference`: dR = dR^ Exp(dtheta), dp, dv, Delta b additive; [theta, p, v, bg, ba]:
/// the right-perturbed increment chart in its own order and sign (identity Jacobians).
class PreintReferenceConvention final
    : public plugin::RightPerturbedIncrementChart<kPreintReferenceOrder, 1> {
 public:
  const char* id() const noexcept override { return ReferenceChart<PreintIncrement>::id; }
};

}  // namespace imuconv::detail
