// imuconv nees: its options and its run, apart from the command line (cmd_nees.cpp maps the
// flags onto NeesCommandOptions), so that a test can run the command without CLI11.
#pragma once

#include <string>
#include <vector>

#include "imuconv/cli/commands.h"

namespace imuconv::cli {

struct NeesCommandOptions {
  std::string imu_path;           ///< --imu: EuRoC/ASL IMU CSV
  std::string ground_truth_path;  ///< --ground-truth: EuRoC/ASL full-state ground truth
  std::string
      noise_path;  ///< --noise: JSON noise object (or a pipeline holding one), or a Kalibr imu.yaml
  std::string pipeline_path;        ///< --pipeline: instead of --imu and --ground-truth
  std::vector<double> windows;      ///< --windows: window lengths in seconds
  std::string method;               ///< --method: a propagator id
  std::string convention = "left";  ///< --convention: state convention of the error and covariance
  double stride = 0.0;      ///< --stride: seconds between window starts; 0: each window's length
  bool as_json = false;     ///< --json: one JSON object instead of the table
  std::string report_path;  ///< --report OUT.html, or empty
};

/// Propagates the windows, prints the summary or JSON on stdout and returns the exit code: 0
/// done, 2 unusable input, 3 internal error (exit_codes.h; nees has no verdict). Throws
/// UsageError when neither --pipeline nor all of --imu, --ground-truth and --noise are given.
[[nodiscard]] int RunNeesCommand(const CommandContext& ctx, const NeesCommandOptions& o);

}  // namespace imuconv::cli
