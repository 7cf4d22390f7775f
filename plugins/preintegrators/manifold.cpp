// `manifold`: GTSAM's ManifoldPreintegration scheme with the covariance of
// PreintegratedCombinedMeasurements (15x15, [theta, p, v, ba, bg], NavState chart of the
// increment, paper eq. residual-error) and the bias Jacobian in dR Exp(dtheta), additive
// dp, dv (paper, "GTSAM Peculiarities", eq. preint-error-dr..db).
// The numerics live in imuconv/kernels/preintegration.h (compiled into imuconv_core).
#include "imuconv/kernels/preintegration.h"
#include "imuconv/plugin_abi.h"

namespace {

class ManifoldPreintegrator final : public imuconv::Preintegrator {
 public:
  const char* id() const noexcept override { return "manifold"; }
  const char* cov_convention() const noexcept override { return "gtsam_manifold"; }
  const char* jacobian_convention() const noexcept override { return "gtsam_manifold_jacobian"; }
  imuconv::Status integrate(const imuconv::PreintegrationInput& in,
                            imuconv::NativePreintegration& out) const noexcept override {
    try {
      return imuconv::kernels::IntegrateManifold(in, out);
    } catch (...) {  // only an allocation failure while reporting an error can get here
      return imuconv::Status::Error("manifold: out of memory");
    }
  }
};

}  // namespace

IMUCONV_PLUGIN(Preintegrator, ManifoldPreintegrator, "manifold", "1.0.0",
               "GTSAM ManifoldPreintegration + combined 15x15 covariance, zero-order hold")
