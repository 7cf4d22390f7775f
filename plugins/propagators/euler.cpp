// `euler`: zero-order hold of knot k over [t_k, t_k+1] (GTSAM's input scheme), with the exact
// Jacobian of the discrete step as transition matrix; native convention `left`.
// The kernel is core/include/imuconv/kernels/euler.h.
#include "imuconv/kernels/mean_only.h"
#include "imuconv/plugin/kernel_registration.h"

// Each sample held over the step it starts: the default cells (forward), densities.
IMUCONV_KERNEL_PROPAGATOR(
    "euler", "1.0.0", "zero-order hold Euler, exact discrete Jacobian, discrete noise; native left",
    imuconv::kernels::HeldPropagation<imuconv::kernels::Hold::Euler>)
