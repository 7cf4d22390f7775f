// `basalt_forward_zoh`: Basalt's preintegration (IntegratedImuMeasurement) with each sample
// held over the step that starts at its timestamp, GTSAM's zero-order hold: the feeding to
// compare Basalt's scheme with GTSAM's `zoh` on the same input. Otherwise as `basalt`.
#include "imuconv/kernels/basalt.h"
#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {
// Each sample held over the step starting at it; the bias constant over the interval, its walk
// only in the increment's bias entries.
struct Scheme : imuconv::kernels::BasaltScheme<imuconv::kernels::BasaltFeeding::kForwardZoh> {
  static constexpr imuconv::NoiseSimulation kNoiseSimulation{
      imuconv::SampleCells::kForward, imuconv::NoiseReading::kWalkInIncrementOnly,
      /*simulable=*/true, ", as Basalt's preintegration assumes (docs/basalt.md)"};
};
}  // namespace

IMUCONV_PLUGIN(Preintegrator, imuconv::plugin::KernelPreintegrator<Scheme>, "basalt_forward_zoh",
               "1.0.0",
               "Basalt IntegratedImuMeasurement, each sample held over the step starting at its "
               "stamp (GTSAM zoh)")
