// FAST-LIO2's IMU forward propagation of one lidar scan (hku-mars/FAST_LIO: ImuProcess's
// forward-propagation loop driving IKFoM's esekf::predict on use-ikfom.hpp's state),
// reproduced to round-off, in IKFoM's own 23-dimensional error state and noise interpretation.
//
// Feeding (ImuProcess): the previous scan ended at t_0, whose IMU message is sample 0; for
// each pair (k, k+1) of samples
//   w = (w_k + w_k+1)/2,  a = ((a_k + a_k+1)/2 * G_m_s2) / |mean_acc|,  dt = t_k+1 - t_k
// (dt from the scan start when sample k lies before it), then one `predict` at the scan end
// with dt = +-(t_scan_end - t_last_sample) (a no-op -0.0 when the scan ends on a sample).
//
// One `predict` (from the pre-step state; exact for the rotation, first order otherwise):
//   pos += vel dt,  rot = rot Exp((w - bg) dt),  vel += (rot (a - ba) + grav) dt,
// biases, extrinsics and gravity unchanged. Its covariance, the note's eq. (prop-cov) one step
// at a time:  P = F P F^T + (dt G) Q (dt G)^T,  F = F_x1 + f_x dt,  with the rotation rows of
// f_x and G multiplied by A(-w dt) = J_r(w dt) (the right Jacobian of SO(3)).
//
// FAST-LIO's quirk, reproduced by default: predict builds F_x1's rotation blocks as
// exp(-w dt) with the half-angle written `scalar_type(1/2)`, an integer division, so they are
// the IDENTITY instead of Exp(-w dt) (IKFoM issue #16). FastLio2Transition::kExactRotation
// puts Exp(-w dt) there: the transition the step implies (d rot_k+1 / d drot_k in the right
// chart). The state itself is not affected (oplus uses the half-angle correctly).
//
// Gravity: an S2 point of fixed length. FAST-LIO's S2<double, 98090, 10000, 1> has length
// 98090/10000 = 9.809 and its constructor rescales any vector to it (FastLio2GravityAsBuilt),
// while the accelerometers are scaled to G_m_s2 = 9.81: FAST-LIO propagates with |g| = 9.809.
//
// Noise, as the code uses it: Q = diag(gyr_cov x3, acc_cov x3, b_gyr_cov x3, b_acc_cov x3)
// enters as Q dt^2 per step, so its entries are per-SAMPLE variances (sigma^2 / dt at the
// nominal rate for a density sigma), and the noise of a step scales with dt^2, not dt.
//
// Error state (23): [pos, rot, offset_R_L_I, offset_T_L_I, vel, bg, ba, grav] with sizes
// [3,3,3,3,3,3,3,2]: pos, offset_T_L_I, vel, bg, ba additive; rot = rot^ Exp(d) (right, body:
// MTK SO3 boxplus), offset_R_L_I likewise; grav = Exp(B(grav^) d) grav^ (MTK S2 boxplus, the
// basis B of S2 type 1, FastLio2S2Basis).
//
// No gravity (length 0, a zero vector: preintegration by propagation, the note's section 3.1)
// is accepted: S2 then has no tangent plane, the gravity rows and columns of the error state
// carry nothing, and its block of F is taken as the identity, the limit of N(g) M(g).
//
// imuconv's 15-dimensional face (PropagateFastLio2, the `fast_lio2*` propagators): the rows
// and columns [pos, rot, vel, bg, ba] of the 23-dimensional error state, in that order, which
// is the state convention `fast_lio2`. With the start covariance zero in the extrinsic and
// gravity blocks, which nothing in a forward propagation couples back into those five blocks
// (F's rows for them have no extrinsic or gravity column but the velocity's gravity column,
// whose covariance stays zero), the restriction is exact: the same numbers as the 23x23 run's.
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "imuconv/export.h"
#include "imuconv/preintegrator.h"
#include "imuconv/propagator.h"
#include "imuconv/status.h"
#include "imuconv/types.h"

namespace imuconv::kernels {

inline constexpr int kFastLio2Dof = 23;
using Vec23 = Eigen::Matrix<double, 23, 1>;
using Mat23 = Eigen::Matrix<double, 23, 23>;

/// Offsets of the blocks of the 23-dimensional error state.
enum FastLio2Block : int {
  kFastLio2Pos = 0,
  kFastLio2Rot = 3,
  kFastLio2OffsetR = 6,
  kFastLio2OffsetT = 9,
  kFastLio2Vel = 12,
  kFastLio2Bg = 15,
  kFastLio2Ba = 18,
  kFastLio2Grav = 21,
};

/// A point of MTK's S2: a vector of fixed length `length`.
struct FastLio2Gravity {
  Vec3 vec = Vec3(0.0, 0.0, -9.809);
  double length = 9.809;
};

/// S2<double, 98090, 10000, 1>(g) as FAST-LIO builds its gravity: g rescaled to 9.809.
IMUCONV_API FastLio2Gravity FastLio2GravityAsBuilt(const Vec3& g);

/// The gravity g itself (length |g|): the S2 members set to the case's gravity; for g = 0 the
/// no-gravity point (length 0).
IMUCONV_API FastLio2Gravity FastLio2GravityExact(const Vec3& g);

/// The orthonormal tangent basis B(vec) (3x2) of MTK's S2 of type 1 (the chart's basis).
IMUCONV_API Eigen::Matrix<double, 3, 2> FastLio2S2Basis(const FastLio2Gravity& g);

/// use-ikfom.hpp's state_ikfom.
struct FastLio2State {
  Vec3 pos = Vec3::Zero();
  Eigen::Quaterniond rot = Eigen::Quaterniond::Identity();  ///< body (IMU) to world
  Eigen::Quaterniond offset_R_L_I = Eigen::Quaterniond::Identity();
  Vec3 offset_T_L_I = Vec3::Zero();
  Vec3 vel = Vec3::Zero();
  Vec3 bg = Vec3::Zero();
  Vec3 ba = Vec3::Zero();
  FastLio2Gravity grav;
};

/// The chart of the error state (header comment): x boxplus d, and its inverse
/// (y boxminus x = d with y = x boxplus d, for |rotations| < pi).
IMUCONV_API FastLio2State FastLio2Boxplus(const FastLio2State& x, const Vec23& d);
IMUCONV_API Vec23 FastLio2Boxminus(const FastLio2State& y, const FastLio2State& x);

/// The parameters ImuProcess reads. The four covariances are the diagonal of Q (per-sample
/// variances, header comment); mean_acc_norm is |mean_acc| of IMU_init.
struct FastLio2Parameters {
  double gyr_cov = 0.0;
  double acc_cov = 0.0;
  double b_gyr_cov = 0.0;
  double b_acc_cov = 0.0;
  double G_m_s2 = 9.81;
  double mean_acc_norm = 9.81;
};

/// Which transition the covariance uses.
enum class FastLio2Transition {
  kAsFastLio,      ///< F_x1's rotation blocks the identity (scalar_type(1/2) = 0), as upstream
  kExactRotation,  ///< those blocks Exp(-w dt): the half-angle that was meant
};

/// One `predict`'s input (ImuProcess's averaged and scaled pair).
struct FastLio2Input {
  Vec3 acc = Vec3::Zero();
  Vec3 gyro = Vec3::Zero();
};

/// One `predict` of the state alone (x_.oplus(f(x, in), dt)).
IMUCONV_API FastLio2State FastLio2PredictState(const FastLio2State& x, const FastLio2Input& in,
                                               double dt);

/// One `predict`'s transition F (F_x1 + f_x dt) and noise Jacobian dt G (23x12, noise order
/// [ng, na, nbg, nba]) at the pre-step state x.
IMUCONV_API void FastLio2StepJacobians(const FastLio2State& x, const FastLio2Input& in, double dt,
                                       FastLio2Transition transition, Mat23& F,
                                       Eigen::Matrix<double, 23, 12>& dt_G);

/// One `predict` call as ImuProcess makes it: its input and its dt.
struct FastLio2Predict {
  FastLio2Input in;
  double dt = 0.0;
};

/// ImuProcess's feeding of one scan (header comment): samples[0] is the previous scan's last
/// IMU message (at or before last_scan_end), the scan ends at scan_end; the last call is the
/// frame-end one. Refuses fewer than two samples, a non-finite value, decreasing stamps,
/// reversed scan ends, a scan with no sample after its start and a non-positive |mean_acc|.
IMUCONV_API Status FastLio2ScanPredicts(const std::vector<ImuSample>& samples,
                                        const FastLio2Parameters& params, double last_scan_end,
                                        double scan_end, std::vector<FastLio2Predict>& predicts);

/// What the forward propagation of one scan returns.
struct FastLio2Propagation {
  int n_predict = 0;             ///< predict calls, the frame-end one included
  double sum_dt = 0.0;           ///< the sum of their dt
  double last_predict_dt = 0.0;  ///< the frame-end predict's dt
  FastLio2State end;
  Mat23 covariance = Mat23::Zero();      ///< from P0
  Mat23 Phi_summed = Mat23::Identity();  ///< the product of every predict's F
  Mat23 Qd_summed = Mat23::Zero();       ///< from P0 = 0: the noise alone
};

/// ImuProcess's forward propagation of one scan: the calls of FastLio2ScanPredicts from
/// `start` with the covariance P0. Refuses what FastLio2ScanPredicts refuses, a non-finite
/// start or P0, a negative gravity length (0 only with a zero vector) and negative variances.
IMUCONV_API Status PropagateFastLio2Scan(
    const std::vector<ImuSample>& samples, const FastLio2Parameters& params, double last_scan_end,
    double scan_end, const FastLio2State& start, const Mat23& P0, FastLio2Propagation& out,
    FastLio2Transition transition = FastLio2Transition::kAsFastLio);

/// How the propagator face reads the four numbers of ImuNoise.
enum class FastLio2NoiseReading {
  /// Continuous densities sigma (imuconv's meaning of ImuNoise), mapped as FAST-LIO's users
  /// set its covariances from a datasheet: Q = sigma^2 f at the nominal rate f, here the
  /// window's mean rate (knots - 1) / (t_e - t_s), one Q for the whole window as ImuProcess
  /// has one (per step Q dt_k^2 = sigma^2 dt_k^2 / mean dt: sigma^2 dt_k on regular sampling).
  kDensities,
  /// FAST-LIO's own numbers, as its configuration file has them and ImuProcess reads them
  /// (mapping/gyr_cov, acc_cov, b_gyr_cov, b_acc_cov: Q's diagonal, per-sample variances),
  /// carried in gyro_noise_density, accel_noise_density, gyro_random_walk, accel_random_walk.
  kAsConfigured,
};

/// One window as FAST-LIO propagates it (header comment), in imuconv's 15-dimensional face:
/// the knots fed as ImuProcess feeds one scan's samples (the first knot as the previous scan's
/// last message, the scan ending on the last knot, so that the frame-end predict is the -0.0
/// no-op), G_m_s2 = |mean_acc| = 9.81 (a factor 1 on the accelerometer, rounded as upstream),
/// start x_s with identity extrinsics and the gravity `in.gravity` as it is given (its own
/// length, FastLio2GravityExact; FAST-LIO's 9.809 is the gravity [0, 0, -9.809] given so),
/// P0 = in.cov_s in [pos, rot, vel, bg, ba] padded with zeros. x_e, Phi and cov are the end
/// state and the [pos, rot, vel, bg, ba] rows and columns of Phi_summed and the covariance.
IMUCONV_API Status PropagateFastLio2(const PropagationInput& in, FastLio2Transition transition,
                                     FastLio2NoiseReading noise, PropagationResult& out);

/// The mean alone of preintegration by propagation of the window with PropagateFastLio2
/// (the start PreintegrationByPropagationStart: identity, zero velocity, the bias estimate,
/// no gravity): dR, dp, dv of the end state, dbg = dba = 0, by the same predicts and state
/// updates, without the 23x23 covariance steps (Monte Carlo trials). Checks its input as
/// PropagateFastLio2 does.
IMUCONV_API Status FastLio2IncrementMean(const PreintegrationInput& in, PreintIncrement& delta);

/// One reading of FAST-LIO as a propagator's kernel (plugin/kernel_plugin.h): native
/// convention `fast_lio2`, its mean alone FastLio2IncrementMean (the transition and the noise
/// do not enter it), and ImuProcess's feeding, the two ends of each step averaged, so that
/// each sample's cell is half of each step beside it. The noise read as FAST-LIO's own
/// per-sample variances is not simulable from densities.
template <FastLio2Transition kTransition, FastLio2NoiseReading kNoise>
struct FastLio2Propagator {
  static constexpr const char* kNativeConvention = "fast_lio2";
  static constexpr NoiseSimulation kNoiseSimulation =
      kNoise == FastLio2NoiseReading::kDensities
          ? NoiseSimulation{SampleCells::kCentered}
          : NoiseSimulation{
                SampleCells::kCentered, NoiseReading::kContinuous, /*simulable=*/false,
                "; MISMATCH: fast_lio2_as_configured reads the four numbers as FAST-LIO's gyr_cov, "
                "acc_cov, b_gyr_cov, b_acc_cov, per-sample variances used as given "
                "(docs/fast-lio2.md), not densities, so the verdict measures that reading, not "
                "the scheme. Use `fast_lio2` for densities"};
  Status operator()(const PropagationInput& in, PropagationResult& out) const {
    return PropagateFastLio2(in, kTransition, kNoise, out);
  }
  static Status Mean(const PreintegrationInput& in, PreintIncrement& delta) {
    return FastLio2IncrementMean(in, delta);
  }
};

/// The readings registered as propagator plugins (plugins/propagators/), each named for what
/// it reads: FAST-LIO as built with densities (`fast_lio2`), as built with its configuration
/// file's own variances (`fast_lio2_as_configured`), and with the rotation block IKFoM meant
/// (`fast_lio2_exact_rotation`).
using FastLio2AsBuilt =
    FastLio2Propagator<FastLio2Transition::kAsFastLio, FastLio2NoiseReading::kDensities>;
using FastLio2AsConfigured =
    FastLio2Propagator<FastLio2Transition::kAsFastLio, FastLio2NoiseReading::kAsConfigured>;
using FastLio2ExactRotation =
    FastLio2Propagator<FastLio2Transition::kExactRotation, FastLio2NoiseReading::kDensities>;

}  // namespace imuconv::kernels
