// OKVIS2's kernel (kernels/okvis2.h) in imuconv's interfaces: what the `okvis2` propagators
// and preintegrator call, once per interval. The arithmetic is the kernel's, compiled in
// imuconv_core; here are only the conversions of its inputs and outputs:
//  - the window's knots become OKVIS's samples, each time as okvis::Time holds it (integer
//    nanoseconds; a knot interpolated at t_s or t_e by the window is a sample of its own, so
//    the kernel never interpolates);
//  - the case's four densities are OKVIS's sigma_g_c, sigma_a_c, sigma_gw_c, sigma_aw_c
//    unchanged: OKVIS reads them as continuous densities too (sigma^2 dt per step), so no
//    mapping and no `_as_configured` form is needed; a_max and g_max keep OKVIS's
//    config/euroc.yaml values (176 m/s^2, 7.8 rad/s), above which OKVIS inflates a step's
//    noise (saturation);
//  - gravity: OKVIS's g_W is (0, 0, g) with the end state r - g_W Dt^2/2, v - g_W Dt. The
//    kernel runs with g = 0 and the input's gravity vector (any direction) is added here the
//    same way; the covariance and the Jacobian do not depend on it;
//  - outputs in the `okvis2` charts: propagation's [r, alpha, v, bg, ba] (world, left
//    rotation; = `left`) and the preintegration's P_delta in the frame S0 with its bias
//    Jacobians from ImuError's first-order correction
//    (Dq = exp(-dalpha_db_g dbg) (x) Delta_q, Delta_p + dp_db_g dbg - C_doubleintegral dba,
//    Delta_v + dv_db_g dbg - C_integral dba).
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "imuconv/kernels/okvis2.h"
#include "imuconv/noise_simulation.h"
#include "imuconv/preintegrated.h"
#include "imuconv/preintegrator.h"
#include "imuconv/propagator.h"

namespace imuconv::kernels {

/// OKVIS's noise for a host that simulates it (noise_simulation.h): each step averages its two
/// samples (trapezoid weights, so centered cells) and the four numbers are continuous densities
/// with the bias walk in the samples, as OKVIS adds sigma^2 dt per step (docs/okvis2.md).
inline constexpr NoiseSimulation kOkvis2NoiseSimulation{SampleCells::kCentered,
                                                        NoiseReading::kContinuous};

/// Every knot of the window as OKVIS stores a sample (okvis::Time stamps).
inline Status Okvis2SamplesOf(const SampleWindow& w, std::vector<Okvis2Sample>& out) {
  out.resize(w.size());
  for (std::size_t j = 0; j < w.size(); ++j) {
    const ImuSample& s = w[j];
    if (Status st = Okvis2TimeFromSeconds(s.t, out[j].t_ns); !st.ok())
      return Status::Error("OKVIS2: knot " + std::to_string(j) + ": " + st.message());
    if (j > 0 && out[j].t_ns <= out[j - 1].t_ns)
      return Status::Error("OKVIS2: knots " + std::to_string(j - 1) + " and " + std::to_string(j) +
                           " fall on the same nanosecond (OKVIS's time unit)");
    out[j].gyro = s.gyro;
    out[j].accel = s.accel;
  }
  return Status::Ok();
}

/// The densities as OKVIS's ImuParameters, gravity left out (added by the caller).
inline Okvis2ImuParameters Okvis2ParametersOf(const ImuNoise& n) {
  Okvis2ImuParameters p;
  p.sigma_g_c = n.gyro_noise_density;
  p.sigma_a_c = n.accel_noise_density;
  p.sigma_gw_c = n.gyro_random_walk;
  p.sigma_aw_c = n.accel_random_walk;
  p.g = 0.0;
  return p;
}

/// ImuError::propagation as a propagator's kernel: end state, Phi = OKVIS's Jacobian and
/// cov = Phi cov_s Phi^T + OKVIS's noise-only covariance, in `okvis2` ([r, alpha, v, bg, ba]).
template <Okvis2Transition kTransition>
struct Okvis2PropagationScheme {
  static constexpr const char* kNativeConvention = "okvis2";
  static constexpr NoiseSimulation kNoiseSimulation = kOkvis2NoiseSimulation;
  Status operator()(const PropagationInput& in, PropagationResult& out) const {
    std::vector<Okvis2Sample> samples;
    if (Status st = Okvis2SamplesOf(in.window, samples); !st.ok()) return st;
    Okvis2Propagation prop;
    if (Status st = PropagateOkvis2(samples, Okvis2ParametersOf(in.noise), Okvis2StateOf(in.x_s),
                                    samples.front().t_ns, samples.back().t_ns, prop, kTransition);
        !st.ok())
      return st;
    const double T = prop.Delta_t;
    out.x_e.R = prop.end.q.toRotationMatrix();
    out.x_e.p = prop.end.r + 0.5 * in.gravity * T * T;
    out.x_e.v = prop.end.v + in.gravity * T;
    out.x_e.bg = prop.end.bg;
    out.x_e.ba = prop.end.ba;
    out.Phi = prop.jacobian;
    out.cov = prop.jacobian * in.cov_s * prop.jacobian.transpose() + prop.covariance;
    return Status::Ok();
  }
};

/// ImuError::redoPreintegration as a preintegrator's kernel: the increment (Delta_q as a
/// rotation matrix, acc_doubleintegral, acc_integral), P_delta and the bias Jacobians, all in
/// the `okvis2` increment chart (J_bias rows [p, alpha, v], columns [bg, ba]).
template <Okvis2Transition kTransition>
struct Okvis2PreintegrationScheme {
  static constexpr const char* kCovConvention = "okvis2";
  static constexpr const char* kJacobianConvention = "okvis2";
  static constexpr NoiseSimulation kNoiseSimulation = kOkvis2NoiseSimulation;
  Status operator()(const PreintegrationInput& in, Preintegrated& out) const {
    std::vector<Okvis2Sample> samples;
    if (Status st = Okvis2SamplesOf(in.window, samples); !st.ok()) return st;
    const std::int64_t t0 = samples.front().t_ns, t1 = samples.back().t_ns;
    Okvis2Preintegration pre;
    if (Status st = PreintegrateOkvis2(samples, Okvis2ParametersOf(in.noise), in.bg, in.ba, t0, t1,
                                       pre, kTransition);
        !st.ok())
      return st;
    out.dt = Okvis2Seconds(t1 - t0);  // ImuError's Delta_t, (t_1 - t_0).toSec()
    // OKVIS never normalizes Delta_q; its norm drifts by rounding only (~1e-13 over 2000
    // steps), and an increment's rotation must be one.
    out.delta.dR = pre.Delta_q.normalized().toRotationMatrix();
    out.delta.dp = pre.acc_doubleintegral;
    out.delta.dv = pre.acc_integral;
    out.delta.dbg.setZero();
    out.delta.dba.setZero();
    out.bg_hat = in.bg;
    out.ba_hat = in.ba;
    out.cov = pre.P_delta;
    out.J_bias.setZero();
    out.J_bias.block<3, 3>(0, 0) = pre.dp_db_g;
    out.J_bias.block<3, 3>(0, 3) = -pre.C_doubleintegral;
    out.J_bias.block<3, 3>(3, 0) = -pre.dalpha_db_g;
    out.J_bias.block<3, 3>(6, 0) = pre.dv_db_g;
    out.J_bias.block<3, 3>(6, 3) = -pre.C_integral;
    return Status::Ok();
  }
};

}  // namespace imuconv::kernels
