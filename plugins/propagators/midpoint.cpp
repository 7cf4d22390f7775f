// `midpoint`: the mean of knots k and k+1 held over [t_k, t_k+1] (OpenVINS' imu_avg, GTSAM's
// reference "mid" input), otherwise the Euler step: the exact Jacobian of the discrete step
// as transition matrix and discrete noise; native convention `left`.
// The kernel is core/include/imuconv/kernels/euler.h.
#include "imuconv/kernels/mean_only.h"
#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {

struct Midpoint : imuconv::kernels::HeldPropagation<imuconv::kernels::Hold::Midpoint> {
  // Averages the two ends of each step: each sample's cell is half of each step beside it.
  static constexpr imuconv::NoiseSimulation kNoiseSimulation{imuconv::SampleCells::kCentered};
};

}  // namespace

IMUCONV_PLUGIN(Propagator, imuconv::plugin::KernelPropagator<Midpoint>, "midpoint", "1.0.0",
               "midpoint-hold Euler, exact discrete Jacobian, discrete noise; native left")
