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
using Scheme =
    imuconv::kernels::VinsFusionScheme<imuconv::kernels::VinsNoiseMapping::kAsConfigured>;
}  // namespace

IMUCONV_PLUGIN(Preintegrator, imuconv::plugin::KernelPreintegrator<Scheme>,
               "vins_fusion_as_configured", "1.0.0",
               "VINS-Fusion IntegrationBase midpoint scheme; noise numbers used as its acc_n, "
               "gyr_n, acc_w, gyr_w")
