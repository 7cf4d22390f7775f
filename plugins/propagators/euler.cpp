// `euler`: zero-order hold of knot k over [t_k, t_k+1] (GTSAM's input scheme), with the exact
// Jacobian of the discrete step as transition matrix; native convention `left`.
// The kernel is core/include/imuconv/kernels/euler.h.
#include "imuconv/kernels/euler.h"
#include "imuconv/kernels/mean_only.h"

#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {

struct Euler {
  imuconv::Status operator()(const imuconv::PropagationInput& in,
                             imuconv::PropagationResult& out) const {
    return imuconv::kernels::PropagateHeld<imuconv::kernels::Hold::Euler>(in, out);
  }
  static imuconv::Status Mean(const imuconv::PreintegrationInput& in,
                              imuconv::PreintIncrement& delta) {
    return imuconv::kernels::HeldIncrementMean<imuconv::kernels::Hold::Euler>(in, delta);
  }
  // Each sample held over the step it starts: the default cells (forward), densities.
};

}  // namespace

IMUCONV_PLUGIN(Propagator, imuconv::plugin::KernelPropagator<Euler>, "euler", "1.0.0",
               "zero-order hold Euler, exact discrete Jacobian, discrete noise; native left")
