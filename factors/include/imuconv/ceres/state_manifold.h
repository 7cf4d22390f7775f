// A ceres::Manifold for one registered state convention: Ceres steps in the chart the user's
// estimator uses, while every cost stays defined in its own fixed charts (factors/README.md:
// why the optimum does not depend on the convention).
#pragma once

#include <ceres/manifold.h>

#include <memory>
#include <string>
#include <string_view>

#include "imuconv/ceres/export.h"
#include "imuconv/chart.h"
#include "imuconv/registry.h"

namespace imuconv::ceres_factors {

/// Ambient 16 (state_block.h), tangent 15 in the convention's own chart and block order:
/// Plus = retract, Minus = local. PlusJacobian = P_left(x) J_left_C(x) and
/// MinusJacobian = J_C_left(x) M_left(x) (state_block.h; J from Registry::to_reference and
/// from_reference), so that a cost's ambient Jacobian H_left M_left(x) times PlusJacobian is the
/// cost's Jacobian in C, and MinusJacobian * PlusJacobian = I. Holds the convention (a
/// shared_ptr, which keeps its plugin loaded) and a pointer to the registry, which must outlive
/// the manifold.
class IMUCONV_CERES_API StateManifold final : public ::ceres::Manifold {
 public:
  /// Throws imuconv::Error for an unknown convention id, listing the known ones.
  StateManifold(const Registry& reg, std::string_view convention);
  int AmbientSize() const override { return 16; }
  int TangentSize() const override { return 15; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
  const std::string& convention() const { return id_; }

 private:
  const Registry* reg_;
  std::string id_;
  std::shared_ptr<const StateConvention> chart_;
};

}  // namespace imuconv::ceres_factors
