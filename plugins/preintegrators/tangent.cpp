// `tangent`: GTSAM's TangentPreintegration scheme with the covariance of
// PreintegratedCombinedMeasurements (15x15, [theta, p, v, ba, bg]) and the bias Jacobian,
// both additive on the tangent 9-vector [theta, p, v] with dR = Exp(theta) (paper,
// "GTSAM Peculiarities": the tangent covariance follows the j perturbation).
// The numerics live in imuconv/kernels/preintegration.h (compiled into imuconv_core).
#include "imuconv/kernels/preintegration.h"
#include "imuconv/plugin_abi.h"

namespace {

class TangentPreintegrator final : public imuconv::Preintegrator {
 public:
  const char* id() const noexcept override { return "tangent"; }
  const char* cov_convention() const noexcept override { return "gtsam_tangent"; }
  const char* jacobian_convention() const noexcept override { return "gtsam_tangent"; }
  imuconv::Status integrate(const imuconv::PreintegrationInput& in,
                            imuconv::NativePreintegration& out) const noexcept override {
    try {
      return imuconv::kernels::IntegrateTangent(in, out);
    } catch (...) {  // only an allocation failure while reporting an error can get here
      return imuconv::Status::Error("tangent: out of memory");
    }
  }
};

}  // namespace

IMUCONV_PLUGIN(Preintegrator, TangentPreintegrator, "tangent", "1.0.0",
               "GTSAM TangentPreintegration + combined 15x15 covariance, zero-order hold")
