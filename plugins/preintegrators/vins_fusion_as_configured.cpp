// `vins_fusion_as_configured`: VINS-Fusion's midpoint preintegration (IntegrationBase) with
// the four noise numbers used as upstream uses its configuration's acc_n, gyr_n, acc_w,
// gyr_w: accel_noise_density is acc_n, gyro_noise_density gyr_n, accel_random_walk acc_w
// and gyro_random_walk gyr_w, each a per-step standard deviation, never divided by dt. Give
// it the values of a VINS-Fusion configuration file to get that run's covariance; the
// covariance is then not that of continuous densities of the same values (about dt/2 of it;
// kernels/vins_fusion.h). Covariance and bias Jacobian in the `vins_fusion` convention.
#include "imuconv/kernels/vins_fusion.h"
#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {
// The midpoint of each step's two ends (centered cells); its noise reading, per-step standard
// deviations with the two ends of a step independent, is one no per-sample noise reproduces.
struct Scheme
    : imuconv::kernels::VinsFusionScheme<imuconv::kernels::VinsNoiseMapping::kAsConfigured> {
  static constexpr imuconv::NoiseSimulation kNoiseSimulation{
      imuconv::SampleCells::kCentered, imuconv::NoiseReading::kContinuous, /*simulable=*/false,
      "; MISMATCH: vins_fusion_as_configured reads the four numbers as VINS-Fusion's per-step "
      "standard deviations (docs/vins-fusion.md), a model no per-sample noise reproduces (it "
      "takes the two ends of a step as independent); with continuous densities its covariance "
      "is about dt/2 of the simulated one, so the verdict measures that reading, not the "
      "scheme. Use `vins_fusion` for densities"};
};
}  // namespace

IMUCONV_PLUGIN(Preintegrator, imuconv::plugin::KernelPreintegrator<Scheme>,
               "vins_fusion_as_configured", "1.0.0",
               "VINS-Fusion IntegrationBase midpoint scheme; noise numbers used as its acc_n, "
               "gyr_n, acc_w, gyr_w")
