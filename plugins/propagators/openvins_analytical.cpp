// `openvins_analytical`: OpenVINS's propagation with IntegrationMethod::ANALYTICAL
// (ov_msckf Propagator: compute_Xi_sum, predict_mean_analytic, compute_F_and_G_analytic).
// Per interval [t_k, t_k+1] the mean w, a of the two bias-corrected knots is held and the
// motion integrated in closed form: with R(s) = Exp(w s), Xi_1 = int_0^dt R(s) ds and
// Xi_2 = int_0^dt int_0^s R(r) dr ds,
//   R' = R Exp(w dt),  v' = v + R Xi_1 a + g dt,  p' = p + v dt + R Xi_2 a + g dt^2/2;
// Xi_3 and Xi_4 are minus the derivatives of Xi_1 a and Xi_2 a with respect to w, so the
// transition
//   F_th,bg = -dR Jl(w dt) dt, F_v,th = -[v' - v - g dt]x R, F_p,th = -[p' - p - v dt - g dt^2/2]x
//   R, F_p,bg = R Xi_4, F_v,bg = R Xi_3, F_p,ba = -R Xi_2, F_v,ba = -R Xi_1
// is the exact derivative of this step (except below |w| = pi/360 rad/s, where OpenVINS
// switches to first-order forms of the Xi, kept here). Qd = G diag(sigma^2 / dt) G^T with G
// the bias columns (measurement noise) and dt I (random walks), for the continuous
// densities sigma (NoiseManager; Trawny eq. 129-130).
// core/include/imuconv/kernels/openvins.h derives the blocks and their form in the `left`
// chart, this plugin's native convention; read in `openvins_jpl` they are OpenVINS's error
// state, and they agree with OpenVINS's own numbers on the ten reference cases to about
// 1e-10 (tests/reference/openvins_rk4_analytical_anchor.cpp).
#include "imuconv/kernels/openvins.h"
#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {
// Its transition and noise (compute_F_and_G_analytic) average the two ends of each step:
// each sample's cell is half of each step beside it.
struct Analytical
    : imuconv::kernels::OpenVinsPropagation<imuconv::kernels::OpenVinsMean::kAnalytical> {
  static constexpr imuconv::NoiseSimulation kNoiseSimulation{imuconv::SampleCells::kCentered};
};
}  // namespace

IMUCONV_PLUGIN(Propagator, imuconv::plugin::KernelPropagator<Analytical>, "openvins_analytical",
               "1.0.0",
               "OpenVINS ANALYTICAL propagation (mean w, a held, closed-form Xi integrals; "
               "compute_F_and_G_analytic transition and noise); native left")
