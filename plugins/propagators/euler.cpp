// `euler`: zero-order hold of knot k over [t_k, t_k+1] (GTSAM's input scheme), with the exact
// Jacobian of the discrete step as transition matrix; native convention `left`.
// The kernel is core/include/imuconv/kernels/euler.h.
#include <exception>
#include <string>

#include "imuconv/kernels/euler.h"
#include "imuconv/plugin_abi.h"

namespace {

class EulerPropagator final : public imuconv::Propagator {
 public:
  const char* id() const noexcept override { return "euler"; }
  const char* native_convention() const noexcept override { return "left"; }
  imuconv::Status propagate(const imuconv::PropagationInput& in,
                            imuconv::PropagationResult& out) const noexcept override {
    try {
      return imuconv::kernels::PropagateHeld<imuconv::kernels::Hold::Euler>(in, out);
    } catch (const std::exception& e) {  // only std::bad_alloc while formatting an error
      return imuconv::Status::Error(std::string("euler: ") + e.what());
    }
  }
};

}  // namespace

IMUCONV_PLUGIN(Propagator, EulerPropagator, "euler", "1.0.0",
               "zero-order hold Euler, exact discrete Jacobian, discrete noise; native left")
