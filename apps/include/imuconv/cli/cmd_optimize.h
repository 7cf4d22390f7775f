// imuconv optimize: its options and its run, apart from the command line (cmd_optimize.cpp maps
// the flags onto OptimizeCommandOptions), so that a test can run the command without CLI11.
// Built only with Ceres (apps/CMakeLists.txt: IMUCONV_HAVE_OPTIMIZE).
#pragma once

#include <string>
#include <vector>

#include "imuconv/cli/commands.h"

namespace imuconv::cli {

struct OptimizeCommandOptions {
  std::string imu_path;            ///< --imu: EuRoC/ASL IMU CSV
  std::string poses_path;          ///< --poses: EuRoC ground truth, EuRoC vicon0 or TUM poses
  std::string noise_path;          ///< --noise: JSON noise (or a pipeline holding one), Kalibr yaml
  std::string pipeline_path;       ///< --pipeline: instead of --imu and --poses
  double keyframe_step = 0.0;      ///< --keyframe-step, seconds
  std::vector<double> pose_sigma;  ///< --pose-sigma METRES,RADIANS (empty: the default)
  std::string method = "manifold";  ///< --method: a propagator or preintegrator id
  std::string convention = "left";  ///< --convention: the chart the solver steps in
  std::string residual = "gtsam";   ///< --residual: gtsam or forster
  double reintegrate_gyro = 0.01;   ///< --reintegrate-gyro, rad/s (VINS-Fusion's)
  double reintegrate_accel = 0.10;  ///< --reintegrate-accel, m/s^2 (VINS-Fusion's)
  int max_rounds = 4;               ///< --max-rounds: solves at most
  int max_iterations = 100;         ///< --max-iterations: per solve
  bool as_json = false;             ///< --json
  std::string output_path;          ///< -o: the JSON or table goes there, not to stdout
  std::string report_path;          ///< --report OUT.html, or empty
};

/// Solves, prints (or writes with -o) the keyframes and the solver summary, and returns the exit
/// code: 0 converged, 1 the solve did not converge (the output says so and is written all the
/// same), 2 unusable input, 3 internal error (exit_codes.h). Throws UsageError when neither
/// --pipeline nor both --imu and --poses are given, or --pose-sigma is not two numbers.
[[nodiscard]] int RunOptimizeCommand(const CommandContext& ctx, const OptimizeCommandOptions& o);

}  // namespace imuconv::cli
