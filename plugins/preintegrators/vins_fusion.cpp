// `vins_fusion`: VINS-Fusion's midpoint preintegration (IntegrationBase), with its own
// first-order Jacobian product and covariance, fed the pipeline's continuous noise
// densities mapped per step so that the covariance is that of continuous white noise:
// acc_n = sigma_a sqrt(2/dt), gyr_n = sigma_g sqrt(2/dt), acc_w = sigma_wa/sqrt(dt),
// gyr_w = sigma_wg/sqrt(dt) at each step's dt (kernels/vins_fusion.h derives it). To
// reproduce a VINS-Fusion run from the four numbers of its configuration file, use
// `vins_fusion_as_configured`.
// Covariance and bias Jacobian in the `vins_fusion` increment convention.
#include "imuconv/kernels/vins_fusion.h"

#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {
// The midpoint of each step's two ends: each sample's cell is half of each step beside it.
struct Scheme
    : imuconv::kernels::VinsFusionScheme<imuconv::kernels::VinsNoiseMapping::kFromDensities> {
  static constexpr imuconv::NoiseSimulation kNoiseSimulation{imuconv::SampleCells::kCentered};
};
}  // namespace

IMUCONV_PLUGIN(Preintegrator, imuconv::plugin::KernelPreintegrator<Scheme>, "vins_fusion", "1.0.0",
               "VINS-Fusion IntegrationBase midpoint scheme; continuous densities mapped per step")
