// `manifold`: GTSAM's ManifoldPreintegration scheme with the covariance of
// PreintegratedCombinedMeasurements (15x15, [theta, p, v, ba, bg], NavState chart of the
// increment, paper eq. residual-error) and the bias Jacobian in dR Exp(dtheta), additive
// dp, dv (paper, "GTSAM Peculiarities", eq. preint-error-dr..db).
// The numerics live in imuconv/kernels/preintegration.h (compiled into imuconv_core).
#include "imuconv/kernels/mean_only.h"
#include "imuconv/kernels/preintegration.h"
#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {

struct Manifold {
  static constexpr const char* kCovConvention = "gtsam_manifold";
  static constexpr const char* kJacobianConvention = "gtsam_manifold_jacobian";
  imuconv::Status operator()(const imuconv::PreintegrationInput& in,
                             imuconv::Preintegrated& out) const {
    return imuconv::kernels::IntegrateManifold(in, out);
  }
  static imuconv::Status Mean(const imuconv::PreintegrationInput& in,
                              imuconv::PreintIncrement& delta) {
    return imuconv::kernels::ManifoldIncrementMean(in, delta);
  }
};

}  // namespace

IMUCONV_PLUGIN(Preintegrator, imuconv::plugin::KernelPreintegrator<Manifold>, "manifold", "1.0.0",
               "GTSAM ManifoldPreintegration + combined 15x15 covariance, zero-order hold")
