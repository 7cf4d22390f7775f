// `openvins_rk4`: OpenVINS's propagation with IntegrationMethod::RK4 (ov_msckf Propagator:
// predict_mean_rk4 for the mean, compute_Xi_sum and compute_F_and_G_analytic for the
// transition and noise). Per interval [t_k, t_k+1] the bias-corrected gyro and accel are
// interpolated linearly between the two knots and the classical four-stage Runge-Kutta step
// moves OpenVINS's JPL quaternion (dq' = Omega(w) dq / 2 from the identity, each stage
// normalised), the velocity (v' = R C(dq)^T a + g) and the position (p' = v). The transition
// and the noise are not the RK4 step's derivative but OpenVINS's closed forms for the mean
// w, a held over the interval (the Xi integrals), evaluated at the RK4 end state:
//   F_th,bg = -dR Jl(w dt) dt, F_v,th = -[v' - v - g dt]x R, F_p,th = -[p' - p - v dt - g dt^2/2]x
//   R, F_p,bg = R Xi_4, F_v,bg = R Xi_3, F_p,ba = -R Xi_2, F_v,ba = -R Xi_1,
// and Qd = G diag(sigma^2 / dt) G^T with G the bias columns (measurement noise) and dt I
// (random walks), for the continuous densities sigma (NoiseManager; Trawny eq. 129-130).
// core/include/imuconv/kernels/openvins.h derives the blocks and their form in the `left`
// chart, this plugin's native convention; read in `openvins_jpl` they are OpenVINS's error
// state, and they agree with OpenVINS's own numbers on the ten reference cases to about
// 1e-10 (tests/reference/openvins_rk4_analytical_anchor.cpp).
#include "imuconv/kernels/openvins.h"
#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {
// RK4 of the linearly interpolated samples: each sample's cell is half of each step beside it.
struct Rk4 : imuconv::kernels::OpenVinsPropagation<imuconv::kernels::OpenVinsMean::kRk4> {
  static constexpr imuconv::NoiseSimulation kNoiseSimulation{imuconv::SampleCells::kCentered};
};
}  // namespace

IMUCONV_PLUGIN(Propagator, imuconv::plugin::KernelPropagator<Rk4>, "openvins_rk4", "1.0.0",
               "OpenVINS RK4 propagation (RK4 of the linearly interpolated samples on the JPL "
               "quaternion, p, v; "
               "compute_F_and_G_analytic transition and noise); native left")
