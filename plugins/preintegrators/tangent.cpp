// `tangent`: GTSAM's TangentPreintegration scheme with the covariance of
// PreintegratedCombinedMeasurements (15x15, [theta, p, v, ba, bg]) and the bias Jacobian,
// both additive on the tangent 9-vector [theta, p, v] with dR = Exp(theta) (paper,
// "GTSAM Peculiarities": the tangent covariance follows the j perturbation).
// The numerics live in imuconv/kernels/preintegration.h (compiled into imuconv_core).
#include "imuconv/kernels/mean_only.h"
#include "imuconv/kernels/preintegration.h"
#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {

struct Tangent {
  static constexpr const char* kCovConvention = "gtsam_tangent";
  static constexpr const char* kJacobianConvention = "gtsam_tangent";
  imuconv::Status operator()(const imuconv::PreintegrationInput& in,
                             imuconv::Preintegrated& out) const {
    return imuconv::kernels::IntegrateTangent(in, out);
  }
  static imuconv::Status Mean(const imuconv::PreintegrationInput& in,
                              imuconv::PreintIncrement& delta) {
    return imuconv::kernels::TangentIncrementMean(in, delta);
  }
};

}  // namespace

IMUCONV_PLUGIN(Preintegrator, imuconv::plugin::KernelPreintegrator<Tangent>, "tangent", "1.0.0",
               "GTSAM TangentPreintegration + combined 15x15 covariance, zero-order hold")
