// `openvins_discrete`: OpenVINS's propagation with IntegrationMethod::DISCRETE (ov_msckf
// Propagator: predict_mean_discrete and compute_F_and_G_discrete), which is the scheme of
// `midpoint`: the bias-corrected mean of samples k and k+1 held over [t_k, t_k+1], the
// rotation by the exact exponential, velocity and position by an Euler step with the
// rotation at t_k, the exact Jacobian of that step as transition matrix, and the noise
// Qd = G Qc G^T with Qc = sigma^2 / dt per interval for the continuous densities sigma
// (OpenVINS's NoiseManager; Trawny and Roumeliotis eq. 129-130).
//
// The id names the system a user brings: its numbers in OpenVINS's error state are those of
// `openvins_jpl` (the run's state_convention), and they agree with OpenVINS's own code on the
// ten reference cases to about 1e-11 (tests/reference/openvins_anchor.cpp). Preintegration
// by propagation with it is GTSAM's manifold preintegration on GTSAM's `mid` input (paper,
// "Forster Preintegration" and "GTSAM Peculiarities"): one computation, two systems.
// The kernel is core/include/imuconv/kernels/euler.h; native convention `left`.
#include "imuconv/kernels/euler.h"
#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {

struct OpenVinsDiscrete {
  imuconv::Status operator()(const imuconv::PropagationInput& in,
                             imuconv::PropagationResult& out) const {
    return imuconv::kernels::PropagateHeld<imuconv::kernels::Hold::Midpoint>(in, out);
  }
  // Averages the two ends of each step: each sample's cell is half of each step beside it.
  static constexpr imuconv::NoiseSimulation kNoiseSimulation{imuconv::SampleCells::kCentered};
};

}  // namespace

IMUCONV_PLUGIN(Propagator, imuconv::plugin::KernelPropagator<OpenVinsDiscrete>, "openvins_discrete",
               "1.0.0",
               "OpenVINS DISCRETE propagation (the midpoint hold: mean of two samples, exact "
               "rotation, Euler v and p); "
               "native left")
