// `basalt`: Basalt's preintegration (IntegratedImuMeasurement) fed as Basalt's VIO feeds it:
// each sample held over the step that ends at its timestamp (the interval's first knot
// unused). Per-sample variances sigma^2/dt at each step's own dt, which are Basalt's
// sigma^2 f on regularly sampled data (kernels/basalt.h). Covariance and bias Jacobian in
// the `basalt` increment convention; the bias blocks are the random walks over the interval.
#include "imuconv/kernels/basalt.h"

#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {
// Each sample held over the step ending at it; the bias constant over the interval, its walk
// only in the increment's bias entries.
struct Scheme : imuconv::kernels::BasaltScheme<imuconv::kernels::BasaltFeeding::kNative> {
  static constexpr imuconv::NoiseSimulation kNoiseSimulation{
      imuconv::SampleCells::kBackward, imuconv::NoiseReading::kWalkInIncrementOnly,
      /*simulable=*/true, ", as Basalt's preintegration assumes (docs/basalt.md)"};
};
}  // namespace

IMUCONV_PLUGIN(
    Preintegrator, imuconv::plugin::KernelPreintegrator<Scheme>, "basalt", "1.0.0",
    "Basalt IntegratedImuMeasurement, each sample held over the step ending at its stamp")
