// OpenVINS's EKF propagation with IntegrationMethod::RK4 and IntegrationMethod::ANALYTICAL
// (ov_msckf Propagator: predict_mean_rk4, predict_mean_analytic, compute_Xi_sum and
// compute_F_and_G_analytic), reproduced to round-off; the DISCRETE method is the `midpoint`
// kernel (euler.h). The state is OpenVINS's IMU without intrinsics or time offset, propagated
// over the window's knots one interval [t_k, t_k+1] at a time, as propagate_and_clone does
// with the knots select_imu_readings returns.
//
// Per interval, dt = t_k+1 - t_k, with the knots' bias-corrected values w_1, a_1 (knot k)
// and w_2, a_2 (knot k+1), and their means w = (w_1 + w_2)/2, a = (a_1 + a_2)/2:
//
// Closed-form integrals (compute_Xi_sum) for w, a held over the interval, with
// K = [w/|w|]x, A = [a]x, th = |w| dt, R(s) = Exp(w s):
//   Xi_1 = int_0^dt R(s) ds,  Xi_2 = int_0^dt int_0^s R(r) dr ds,
//   Xi_3, Xi_4: the derivatives of Xi_1 a and Xi_2 a with respect to w, up to sign
//   (d (Xi_1 a) = -Xi_3 dw, d (Xi_2 a) = -Xi_4 dw), each a combination of A, AK, KA, AK^2,
//   K^2A + (k.a) K and (k.a) K^2 with coefficients in th, sin th, cos th.
// Below |w| = pi/360 rad/s OpenVINS switches to first-order forms that are not these
// integrals (Xi_1 = dt Exp(w dt), Xi_2 = Xi_1 dt/2, and likewise for Xi_3, Xi_4); they are kept,
// since they are what OpenVINS computes for a slowly turning IMU.
//
// Mean (R body-to-world, g the gravity vector, here added rather than subtracted):
//   analytical:  R' = R Exp(w dt),  v' = v + R Xi_1 a + g dt,  p' = p + v dt + R Xi_2 a + g dt^2/2;
//   rk4:         w, a interpolated linearly from knot k to knot k+1 and the classical
//                four-stage Runge-Kutta step on OpenVINS's JPL quaternion dq (from the
//                interval's start; dq' = Omega(w) dq / 2, each stage's dq normalised before
//                use), and on p, v with v' = R C(dq)^T a + g; R' = R C(dq)^T.
//
// Transition and noise (compute_F_and_G_analytic) for both, in OpenVINS's error state
// [theta, p, v, bg, ba] (R = R^ Exp(theta), body frame):
//   F_th,th = dR = R'^T R,  F_th,bg = -dR Jl(w dt) dt,
//   F_p,th = -[p' - p - v dt - g dt^2/2]x R,  F_v,th = -[v' - v - g dt]x R,  F_p,v = dt I,
//   F_p,bg = R Xi_4,  F_v,bg = R Xi_3,  F_p,ba = -R Xi_2,  F_v,ba = -R Xi_1;
//   G = the bias columns of F without the identity for the measurement noise (n_g, n_a),
//   and dt I for the random walks; Qd = G diag(sigma^2/dt) G^T (Trawny eq. 129-130), which
//   for the walks is sigma_w^2 dt. (For rk4 these are the analytical ones at the means w, a,
//   not the derivative of the RK4 step: upstream's choice, kept.)
//
// The kernel works in imuconv's `left` chart ([p, theta, v, bg, ba], R = Exp(theta) R^):
// theta_left = R theta_ov, so the step's transition is T F T^-1 with that rotation at each
// end, which is the block form of left_transition.h with
//   th_bg = -R Jl(w dt) dt,  p_th = -[p' - p - v dt - g dt^2/2]x,  v_th = -[v' - v - g dt]x,
//   p_v = dt,  p_bg = R Xi_4,  v_bg = R Xi_3,  p_ba = -R Xi_2,  v_ba = -R Xi_1
// (F_th,th becomes R' dR R^T = I). A linear change of chart at each end commutes with the
// products Phi = F_N ... F_1 and Qd_k+1 = F Qd_k F^T + Qd_i, so the result is OpenVINS's up to
// rounding; the registry converts it to `openvins_jpl`, whose Jacobian is OpenVINS's error state.
// The covariance is Phi P_s Phi^T + Qd as StateHelper::EKFPropagation forms it.
//
// Two of OpenVINS's thresholds change numbers beyond rounding and are kept: Jl is the
// identity below |w dt| = 1e-6, and the small-|w| forms above.
#pragma once

#include "imuconv/export.h"
#include "imuconv/kernels/common.h"
#include "imuconv/propagator.h"
#include "imuconv/status.h"
#include "imuconv/types.h"

namespace imuconv::kernels {

/// How OpenVINS moves the mean over one interval (StateOptions::IntegrationMethod).
enum class OpenVinsMean { kRk4, kAnalytical };

/// compute_Xi_sum of one interval, with w and a held: see the file comment.
struct OpenVinsIntegrals {
  Mat3 Xi1, Xi2, Xi3, Xi4;
  Mat3 Jl;  ///< OpenVINS's Jr_so3(-w dt) = Jl(w dt), the identity below |w dt| = 1e-6
};

/// The integrals of one interval of length dt with bias-corrected w and a held. Xi3, Xi4 and
/// Jl are left unset unless `derivatives` (the mean needs Xi1 and Xi2 only).
IMUCONV_API void OpenVinsIntegralsOf(double dt, const Vec3& w, const Vec3& a, bool derivatives,
                                     OpenVinsIntegrals& xi);

/// Propagates over the window as OpenVINS does with `mean` (see the file comment), in the
/// `left` chart: the end state always, Phi and the covariance as `outputs` asks (the reduced
/// modes serve finite differences and Monte Carlo). Checks the input (CheckPropagationInput).
IMUCONV_API Status PropagateOpenVins(const PropagationInput& in, OpenVinsMean mean,
                                     PropagationResult& out, Outputs outputs = Outputs::All);

/// One method as a propagator's kernel (plugin/kernel_plugin.h; native convention `left`).
template <OpenVinsMean kMean>
struct OpenVinsPropagation {
  Status operator()(const PropagationInput& in, PropagationResult& out) const {
    return PropagateOpenVins(in, kMean, out);
  }
};

}  // namespace imuconv::kernels
