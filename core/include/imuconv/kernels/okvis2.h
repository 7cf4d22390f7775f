// OKVIS2's IMU propagation and preintegration (ethz-mrl/okvis2, okvis_ceres ImuError:
// `propagation`, `redoPreintegration`, `EvaluateWithMinimalJacobians`), reproduced to
// round-off, in OKVIS's own error state, noise interpretation and time stamps.
//
// The step over samples k, k+1 (dt from OKVIS's integer nanosecond stamps):
//   w   = (w_k + w_k+1)/2 - bg,  a = (a_k + a_k+1)/2 - ba
//   Dq' = Dq (x) exp(w dt)                       -- never normalized
//   C, C' the rotation matrices of Dq, Dq' (Eigen's formula, also for a non-unit Dq)
//   acc_integral'        = acc_integral + (C + C') a dt/2
//   acc_doubleintegral  += acc_integral dt + (C + C') a dt^2/4   (trapezoid on the rotation)
//   C_integral, C_doubleintegral likewise with a replaced by the identity
// The bias Jacobians are running sums: d alpha/d bg as sum dt C' in `propagation` and as
// sum C' Jr(w dt) dt in `redoPreintegration` (the two differ by the right Jacobian Jr).
//
// OKVIS's per-step transition F_delta (15x15, order [p, alpha, v, bg, ba]) puts
// whole-interval sums into three blocks (F(p, alpha) holds acc_integral, F(p, bg) and
// F(v, bg) hold dv/dbg and `cross`, sensitivities to the bias at the interval START, and
// F(p, ba) holds C_integral): the product of the F_delta is not the linearization of OKVIS's
// own increments, and its covariance overstates the position variance (1.3 to 9.4 times on
// the reference cases, tests/data/reference/anchors/README.md). Reproduced as it is here;
// kOkvisStepLocal makes those blocks step-local, the transition the scheme implies.
//
// Noise, as OKVIS uses its four numbers: continuous densities, per step
//   alpha: sigma_g^2 dt,  v: sigma_a^2 dt,  p: sigma_a^2 dt^3/2 (no p-v cross term),
//   bg: sigma_gw^2 dt,  ba: sigma_aw^2 dt,
// each multiplied by 100 (squared) for a step whose samples exceed a_max or g_max
// (saturation); `propagation` multiplies its velocity variance by the saturated sigma_a only
// once, as upstream does.
//
// Error states (OKVIS's, all additive but the rotation):
//  - propagation's covariance and Jacobian: [r, alpha, v, bg, ba], r = r^ + dr (world),
//    C_WS = Exp(dalpha) C_WS^ (LEFT, world frame: PoseManifold::plus), v world;
//  - the preintegration's P_delta: the same blocks in the frame S0 of the first state, the
//    increment's rotation Exp(dalpha) Delta_C^ (left).
// The ImuError residual is [position, 2 vec(Dq (x) q_1^-1 (x) q_0), velocity, b_0 - b_1]
// with the first-order bias correction (Dq = exp(-dalpha/dbg dbg) (x) Delta_q).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "imuconv/export.h"
#include "imuconv/kernels/system_state.h"
#include "imuconv/status.h"
#include "imuconv/types.h"

namespace imuconv::kernels {

/// okvis::ImuParameters' fields that the propagation reads. a_max and g_max are the
/// saturation limits (config/euroc.yaml's values by default), g the gravity magnitude
/// (gravity is -g along the world z axis).
struct Okvis2ImuParameters {
  double sigma_g_c = 0.0;   ///< gyro noise density, rad/s/sqrt(Hz)
  double sigma_a_c = 0.0;   ///< accelerometer noise density, m/s^2/sqrt(Hz)
  double sigma_gw_c = 0.0;  ///< gyro bias random walk, rad/s^2/sqrt(Hz)
  double sigma_aw_c = 0.0;  ///< accelerometer bias random walk, m/s^3/sqrt(Hz)
  double a_max = 176.0;
  double g_max = 7.8;
  double g = 9.81;
};

/// One IMU sample as OKVIS stores it: an integer nanosecond stamp.
struct Okvis2Sample {
  std::int64_t t_ns = 0;
  Vec3 gyro = Vec3::Zero();
  Vec3 accel = Vec3::Zero();
};

/// okvis::Time(t): whole seconds floor(t), nanoseconds round((t - floor t) 1e9), as one
/// count of nanoseconds. Refuses a time that is not finite or outside OKVIS's unsigned
/// 32-bit seconds.
IMUCONV_API Status Okvis2TimeFromSeconds(double t, std::int64_t& t_ns);

/// okvis::Duration's toSec() of a nanosecond count: whole seconds + 1e-9 nanoseconds.
IMUCONV_API double Okvis2Seconds(std::int64_t duration_ns);

/// OKVIS's pose and speed-and-biases.
struct Okvis2State {
  Vec3 r = Vec3::Zero();                                  ///< position in world
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  ///< body to world
  Vec3 v = Vec3::Zero();                                  ///< velocity in world
  Vec3 bg = Vec3::Zero();
  Vec3 ba = Vec3::Zero();
};

/// `x` as OKVIS's state: the same position, rotation (as a quaternion), velocity and biases.
inline Okvis2State Okvis2StateOf(const ImuState& x) {
  return SystemStateOf(x, &Okvis2State::r, &Okvis2State::q, &Okvis2State::v, &Okvis2State::bg,
                       &Okvis2State::ba);
}

/// Which transition the covariance uses.
enum class Okvis2Transition {
  kAsOkvis,         ///< upstream's F_delta, whole-interval sums in three blocks (see above)
  kOkvisStepLocal,  ///< those three blocks step-local: the linearization of the step
};

/// What ImuError::propagation returns.
struct Okvis2Propagation {
  int steps = 0;         ///< steps integrated (upstream's return value)
  double Delta_t = 0.0;  ///< sum of the steps' dt
  Okvis2State end;
  Mat15 covariance = Mat15::Zero();    ///< noise-only covariance of the end state
  Mat15 jacobian = Mat15::Identity();  ///< d end / d start
};

/// ImuError::propagation over [t_start_ns, t_end_ns] (samples must cover it; a sample
/// straddling either end is interpolated linearly, as upstream does).
IMUCONV_API Status PropagateOkvis2(const std::vector<Okvis2Sample>& samples,
                                   const Okvis2ImuParameters& params, const Okvis2State& start,
                                   std::int64_t t_start_ns, std::int64_t t_end_ns,
                                   Okvis2Propagation& out,
                                   Okvis2Transition transition = Okvis2Transition::kAsOkvis);

/// What ImuError holds after redoPreintegration at a bias.
struct Okvis2Preintegration {
  int steps = 0;
  Eigen::Quaterniond Delta_q = Eigen::Quaterniond::Identity();
  Mat3 C_integral = Mat3::Zero();
  Mat3 C_doubleintegral = Mat3::Zero();
  Vec3 acc_integral = Vec3::Zero();
  Vec3 acc_doubleintegral = Vec3::Zero();
  Mat3 dalpha_db_g = Mat3::Zero();
  Mat3 dv_db_g = Mat3::Zero();
  Mat3 dp_db_g = Mat3::Zero();
  Vec3 bg_ref = Vec3::Zero();  ///< the biases it was integrated at (speedAndBiases_ref)
  Vec3 ba_ref = Vec3::Zero();
  Mat15 P_delta = Mat15::Zero();      ///< [p, alpha, v, bg, ba] in frame S0
  Mat15 information = Mat15::Zero();  ///< P_delta's pseudo-inverse as OKVIS forms it
};

/// ImuError::redoPreintegration at the biases bg, ba over [t0_ns, t1_ns].
IMUCONV_API Status PreintegrateOkvis2(const std::vector<Okvis2Sample>& samples,
                                      const Okvis2ImuParameters& params, const Vec3& bg,
                                      const Vec3& ba, std::int64_t t0_ns, std::int64_t t1_ns,
                                      Okvis2Preintegration& out,
                                      Okvis2Transition transition = Okvis2Transition::kAsOkvis);

/// ImuError's information from its P_delta (symmetric): OKVIS's pseudo-inverse, eigenvalues
/// at or below eps * max(1, 15 * largest) replaced by that floor (PseudoInverse::symmSqrtU,
/// information = U^T U). PreintegrateOkvis2 fills Okvis2Preintegration::information with it;
/// the `okvis2` residual plugin forms it from a measurement's covariance.
IMUCONV_API void Okvis2Information(const Mat15& P_delta, Mat15& information);

/// ImuError's residual and Jacobians before weighting (OKVIS multiplies all of them by the
/// square root of `information`, whose rows' signs are an eigen-solver's choice).
struct Okvis2ImuErrorTerms {
  Vec15 residual = Vec15::Zero();
  Eigen::Matrix<double, 15, 7> jacobian_pose_0 = Eigen::Matrix<double, 15, 7>::Zero();
  Eigen::Matrix<double, 15, 9> jacobian_speedbias_0 = Eigen::Matrix<double, 15, 9>::Zero();
  Eigen::Matrix<double, 15, 7> jacobian_pose_1 = Eigen::Matrix<double, 15, 7>::Zero();
  Eigen::Matrix<double, 15, 9> jacobian_speedbias_1 = Eigen::Matrix<double, 15, 9>::Zero();
  Eigen::Matrix<double, 15, 6> jacobian_pose_0_minimal = Eigen::Matrix<double, 15, 6>::Zero();
  Eigen::Matrix<double, 15, 6> jacobian_pose_1_minimal = Eigen::Matrix<double, 15, 6>::Zero();
};

/// EvaluateWithMinimalJacobians with the preintegration `pre` (its bias is the
/// linearization point; state_0's biases away from it enter to first order), Delta_t the
/// interval's length. The quaternions are normalized first, as upstream reads them.
/// Ceres pose blocks are [x y z qx qy qz qw]; minimal pose increments [dr, dalpha] of
/// PoseManifold::plus; speed-and-bias blocks [v, bg, ba], additive.
IMUCONV_API Okvis2ImuErrorTerms EvaluateOkvis2ImuError(const Okvis2Preintegration& pre,
                                                       const Okvis2ImuParameters& params,
                                                       double Delta_t, const Okvis2State& state_0,
                                                       const Okvis2State& state_1);

/// Whether ImuError re-integrates before evaluating at state_0's biases: upstream does when
/// the gyro bias moved by more than 3e-4 rad/s from the linearization point AND the
/// interval holds fewer than 50 samples (or it was never integrated).
IMUCONV_API bool Okvis2RedoesPreintegration(const Okvis2Preintegration& pre, const Vec3& bg_0,
                                            std::size_t n_samples);

}  // namespace imuconv::kernels
