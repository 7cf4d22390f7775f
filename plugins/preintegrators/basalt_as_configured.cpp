// `basalt_as_configured`: Basalt's preintegration (IntegratedImuMeasurement) fed as Basalt's
// VIO feeds it (each sample held over the step ending at its stamp), with the two white-noise
// numbers used as Basalt's integrate() receives them: gyro_noise_density and
// accel_noise_density are the per-sample standard deviations, dicrete_time_*_noise_std() =
// calibration density x sqrt(imu_update_rate), constant whatever each step's dt. Give it
// sigma_c sqrt(rate) from a Basalt calibration to get that run's covariance, also on
// irregularly sampled data, where `basalt` (sigma^2 / dt per step) differs by the jitter. The
// random walks stay densities (the bias blocks, sigma_b^2 T). Covariance and bias Jacobian in
// the `basalt` increment convention (kernels/basalt.h).
#include "imuconv/kernels/basalt.h"
#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {
// Each sample held over the step ending at it; the white-noise numbers read as per-sample
// standard deviations (Basalt's dicrete_time_*_noise_std), the walk only in the increment.
struct Scheme
    : imuconv::kernels::BasaltScheme<imuconv::kernels::BasaltFeeding::kNative,
                                     imuconv::kernels::BasaltNoiseMapping::kAsConfigured> {
  static constexpr imuconv::NoiseSimulation kNoiseSimulation{
      imuconv::SampleCells::kBackward, imuconv::NoiseReading::kPerSampleStd, /*simulable=*/true,
      ", as basalt_as_configured reads them (Basalt's dicrete_time_*_noise_std), each sample "
      "held over the step ending at it; bias random walk (densities) in the increment's bias "
      "entries only (docs/basalt.md)"};
};
}  // namespace

IMUCONV_PLUGIN(Preintegrator, imuconv::plugin::KernelPreintegrator<Scheme>, "basalt_as_configured",
               "1.0.0",
               "Basalt IntegratedImuMeasurement, native feeding; noise numbers used as its "
               "per-sample standard deviations")
