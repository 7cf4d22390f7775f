// GTSAM's two preintegration schemes (kernels/preintegration.h) as a preintegrator's kernel
// (plugin/kernel_plugin.h), the `manifold` and `tangent` plugins: the full run with the
// covariance of PreintegratedCombinedMeasurements, the mean alone (kernels/mean_only.h) and
// the increment charts each scheme reports in (paper, "GTSAM Peculiarities"). The two differ
// only in which scheme runs and in those charts.
#pragma once

#include "imuconv/kernels/mean_only.h"
#include "imuconv/kernels/preintegration.h"

namespace imuconv::kernels {

/// Which of GTSAM's preintegrations: ManifoldPreintegration (the increment a NavState) or
/// TangentPreintegration (the tangent 9-vector [theta, p, v] with dR = Exp(theta)).
enum class GtsamPreintegration { kManifold, kTangent };

template <GtsamPreintegration kScheme>
struct GtsamScheme {
  static constexpr bool kManifold = kScheme == GtsamPreintegration::kManifold;
  /// manifold: the covariance in the NavState chart of the increment (eq. residual-error),
  /// the bias Jacobian in dR Exp(dtheta), additive dp, dv (eq. preint-error-dr..db);
  /// tangent: both additive on the tangent 9-vector.
  static constexpr const char* kCovConvention = kManifold ? "gtsam_manifold" : "gtsam_tangent";
  static constexpr const char* kJacobianConvention =
      kManifold ? "gtsam_manifold_jacobian" : "gtsam_tangent";
  Status operator()(const PreintegrationInput& in, Preintegrated& out) const {
    return kManifold ? IntegrateManifold(in, out) : IntegrateTangent(in, out);
  }
  static Status Mean(const PreintegrationInput& in, PreintIncrement& delta) {
    return kManifold ? ManifoldIncrementMean(in, delta) : TangentIncrementMean(in, delta);
  }
};

}  // namespace imuconv::kernels
