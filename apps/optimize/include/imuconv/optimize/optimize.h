// imuconv optimize: a batch estimate of every keyframe's state over a sequence, from the IMU
// samples and pose measurements, with preintegration factors (the note, section 4.3) in Ceres.
//
// The problem. Keyframes every `keyframe_step` seconds over the span the IMU data and the poses
// share; one 16-double state block [p, q_wxyz, v, bg, ba] each (imuconv/ceres/state_block.h).
// Costs, all functions of the states alone in their own fixed charts, so that the optimum does
// not depend on the convention the solver steps in:
//   - between consecutive keyframes, a PreintegrationFactor of `method` (any propagator, by
//     propagation, or native preintegrator) with the residual kind `kind` (GTSAM's by default),
//     whose bias rows carry the bias random walk of the noise densities over the interval;
//   - at each keyframe, a pose measurement (the poses interpolated at its time: p linearly, R by
//     slerp) with standard deviations pose_sigma_m and pose_sigma_rad;
//   - on the first keyframe, a weak prior (WeakPriorSigmas), always in the chart `left`: it
//     only keeps the normal equations regular when few keyframes see the biases; its
//     information is far below the data's, so it moves the optimum by a negligible fraction.
// Only the manifold, the convention `convention`, changes with the user's chart; the marginal
// covariances come out in it (its block order and labels).
//
// The solve: Levenberg-Marquardt with sparse normal Cholesky (SuiteSparse); then every factor
// whose start bias estimate has moved from its linearization bias beyond the thresholds is
// re-integrated at the new bias (VINS-Fusion's repropagate) and the problem solved again, until
// none moves or max_rounds solves have run.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "imuconv/bridge.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/registry.h"

namespace imuconv::optimize {

/// The most keyframes one solve takes, checked from span / step before anything is stored:
/// nees's limit on windows (kMaxWindows), the count of integrations over one sequence. A
/// keyframe costs some 45 KB here (state block, factor, Ceres's residual and Jacobian blocks:
/// the V1_01 slice at 1000 and 2000 keyframes took 60 and 106 MB), so 1e6 keyframes are already
/// tens of GB; below it, every interval must also hold a sample strictly inside, so the count is
/// at most the IMU samples' and the memory grows with the input, not with a tiny step.
constexpr std::size_t kMaxKeyframes = 1000000;

/// The prior on the first keyframe (standard deviations, in the chart `left`): it centres on the
/// first pose measurement, the velocity from a central difference of the poses, zero biases.
/// Each is far wider than what the data determine (a pose sigma of millimetres, biases to 1e-4)
/// and wider than the quantity itself on any MEMS IMU (turn-on biases of 1e-2 rad/s and 1e-1
/// m/s^2): the prior's weight on the estimate is the ratio of the posterior to the prior
/// variance, 1e-6 or less.
struct WeakPriorSigmas {
  double theta_rad = 1.0;
  double p_m = 1.0;
  double v_mps = 1.0;
  double bg_radps = 0.1;
  double ba_mps2 = 1.0;
};

struct Options {
  std::string method = "manifold";  ///< a propagator or preintegrator id
  std::string convention = "left";  ///< the state convention the solver steps in
  ResidualKind kind = ResidualKind::Gtsam;
  double keyframe_step = 0.0;  ///< seconds between keyframes (each interval holds a sample)
  double pose_sigma_m = 0.01;  ///< pose measurement's position standard deviation
  double pose_sigma_rad = 0.01;
  /// Re-integration thresholds on the norm of the bias change, VINS-Fusion's (imu_factor.h:
  /// 0.01 rad/s gyro, 0.10 m/s^2 accel).
  double reintegrate_gyro = 0.01;
  double reintegrate_accel = 0.10;
  int max_rounds = 4;        ///< solves at most (the first, and re-integrated ones)
  int max_iterations = 100;  ///< per solve
  WeakPriorSigmas prior;
  ImuNoise noise;
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  bool covariance = true;  ///< compute each keyframe's marginal covariance
};

struct Keyframe {
  double t = 0.0;  ///< seconds relative to the IMU data's origin
  ImuState x;
  Mat15 cov = Mat15::Zero();  ///< in `convention`'s chart and block order
  /// The poses file's biases at t (EuRoC ground truth), when it has them.
  bool has_reference_bias = false;
  Vec3 ref_bg = Vec3::Zero(), ref_ba = Vec3::Zero();
};

/// One solve and what preceded it.
struct Round {
  int iterations = 0;  ///< Ceres's iterations (its summary's, the zeroth included)
  double initial_cost = 0.0, final_cost = 0.0;
  std::string termination;  ///< CONVERGENCE, NO_CONVERGENCE, FAILURE, ...
  double seconds = 0.0;
  /// Factors re-integrated after this solve (zero on the last round).
  int reintegrated = 0;
};

/// The estimated biases against the poses file's (only when it has them), per axis.
struct BiasComparison {
  Vec3 rms_bg = Vec3::Zero(), rms_ba = Vec3::Zero();  ///< RMS of estimate - reference
  /// Fraction of keyframes whose |estimate - reference| <= 3 sigma (sigma from the marginal
  /// covariance's diagonal).
  Vec3 within_3sigma_bg = Vec3::Zero(), within_3sigma_ba = Vec3::Zero();
};

struct Result {
  std::string method, convention, kind;
  std::vector<std::string> labels;  ///< the convention's five block labels, in its order
  double keyframe_step = 0.0;
  ImuNoise noise;
  std::vector<Keyframe> keyframes;
  std::vector<Round> rounds;
  int factors = 0;
  bool converged = false;  ///< the last solve ended in CONVERGENCE
  /// Factors whose start bias moved beyond the thresholds after the last solve (max_rounds
  /// reached): first-order corrected, not re-integrated.
  int pending_reintegration = 0;
  std::string solver_message;  ///< Ceres's last message
  bool covariance_ok = false;  ///< every marginal computed (false: not asked, or rank deficient)
  std::string covariance_message;
  double covariance_seconds = 0.0;  ///< wall time of ceres::Covariance's Compute and blocks
  bool has_reference_bias = false;
  BiasComparison bias;
};

/// Builds and solves the problem. Throws Error (the option named) for an unknown method or
/// convention, all-zero noise densities, a pose sigma below kMinPoseSigma, a keyframe step not
/// finite, below the IMU's median sample period, longer than the span the samples and the poses
/// share, giving more than kMaxKeyframes keyframes, or leaving an interval without a sample
/// strictly inside it (interval_samples.h). A final cost that is not finite is not converged.
Result RunOptimize(const Registry& reg, const pipeline::ImuData& imu,
                   const pipeline::GroundTruth& poses, const Options& options);

}  // namespace imuconv::optimize
