// `midpoint`: the mean of knots k and k+1 held over [t_k, t_k+1] (OpenVINS' imu_avg, GTSAM's
// reference "mid" input), otherwise the Euler step: the exact Jacobian of the discrete step
// as transition matrix and discrete noise; native convention `left`.
// The kernel is core/include/imuconv/kernels/euler.h.
#include <exception>
#include <string>

#include "imuconv/kernels/euler.h"
#include "imuconv/plugin_abi.h"

namespace {

class MidpointPropagator final : public imuconv::Propagator {
 public:
  const char* id() const noexcept override { return "midpoint"; }
  const char* native_convention() const noexcept override { return "left"; }
  imuconv::Status propagate(const imuconv::PropagationInput& in,
                            imuconv::PropagationResult& out) const noexcept override {
    try {
      return imuconv::kernels::PropagateHeld<imuconv::kernels::Hold::Midpoint>(in, out);
    } catch (const std::exception& e) {  // only std::bad_alloc while formatting an error
      return imuconv::Status::Error(std::string("midpoint: ") + e.what());
    }
  }
};

}  // namespace

IMUCONV_PLUGIN(Propagator, MidpointPropagator, "midpoint", "1.0.0",
               "midpoint-hold Euler, exact discrete Jacobian, discrete noise; native left")
