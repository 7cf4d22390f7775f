// `rk4`: fourth-order integration of the continuous-time model with the input interpolated
// linearly between knots, one step per knot interval; native convention `left`. Since 1.1.0
// it is no longer the classical Runge-Kutta tableau: the rotation is the fourth-order Magnus
// expansion, everything else quadratures at the nodes 0, h/2, h, and the covariance comes by
// variation of constants. It agrees with the classical RK4 (kept in the tests as the
// cross-check) to O(h^4); the id keeps its name so that configurations keep working.
// The kernel is compiled in imuconv_core (core/include/imuconv/kernels/rk4.h, its code in
// core/src/kernels/rk4_window.h); this plugin only names it.
#include "imuconv/kernels/rk4.h"
#include "imuconv/kernels/mean_only.h"

#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {

struct Rk4 {  // one step per knot interval
  imuconv::Status operator()(const imuconv::PropagationInput& in,
                             imuconv::PropagationResult& out) const {
    return imuconv::kernels::PropagateRk4(in, out, 1);
  }
  static imuconv::Status Mean(const imuconv::PreintegrationInput& in,
                              imuconv::PreintIncrement& delta) {
    return imuconv::kernels::Rk4IncrementMean(in, 1, delta);
  }
  // Interpolates linearly between knots: each sample's cell is half of each step beside it.
  static constexpr imuconv::NoiseSimulation kNoiseSimulation{imuconv::SampleCells::kCentered};
};

}  // namespace

IMUCONV_PLUGIN(Propagator, imuconv::plugin::KernelPropagator<Rk4>, "rk4", "1.1.0",
               "4th-order (Magnus + node quadratures) state, Phi and covariance, linearly "
               "interpolated input; native left")
