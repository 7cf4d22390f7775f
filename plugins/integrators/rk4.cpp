// `rk4`: classical fourth-order Runge-Kutta on the state (Lie-group form for the rotation),
// the transition matrix and the covariance together, input interpolated linearly between
// knots, one step per knot interval; native convention `left`.
// The kernel is core/include/imuconv/kernels/rk4.h.
#include <exception>
#include <string>

#include "imuconv/kernels/rk4.h"
#include "imuconv/plugin_abi.h"

namespace {

class Rk4Propagator final : public imuconv::Propagator {
 public:
  const char* id() const noexcept override { return "rk4"; }
  const char* native_convention() const noexcept override { return "left"; }
  imuconv::Status propagate(const imuconv::PropagationInput& in,
                            imuconv::PropagationResult& out) const noexcept override {
    try {
      return imuconv::kernels::PropagateRk4(in, out, 1);
    } catch (const std::exception& e) {  // only std::bad_alloc while formatting an error
      return imuconv::Status::Error(std::string("rk4: ") + e.what());
    }
  }
};

}  // namespace

IMUCONV_PLUGIN(Propagator, Rk4Propagator, "rk4", "1.0.0",
               "RK4 of state, Phi and covariance with linearly interpolated input; native left")
