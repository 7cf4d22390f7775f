// The inputs of imuconv optimize: the IMU samples, the pose measurements on their time axis, and
// (from a pipeline) the noise and gravity. Either EuRoC/ASL IMU with a pose file whose format is
// recognised from its first data row (EuRoC/ASL full-state ground truth, EuRoC vicon0 poses, or a
// TUM trajectory), or a pipeline whose /imu, /ground_truth, /noise and /gravity are read as
// `imuconv run` reads them. The readers are the ones nees uses; their errors name the file and
// line or the JSON pointer.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "imuconv/pipeline/imu_reader.h"

namespace imuconv::optimize {

struct Input {
  pipeline::ImuData imu;
  /// The pose measurements; when full_state (an EuRoC ground-truth file) its biases are the
  /// reference the estimated biases are compared with (never used by the estimate itself).
  pipeline::GroundTruth poses;
  std::optional<ImuNoise> noise;  ///< the pipeline's /noise, when it has one
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  std::vector<std::string> warnings;  ///< the samples' plausibility warnings, and the poses'
};

/// The ground-truth format of a pose file by its first data row: 17 comma-separated fields
/// "euroc" (full state), 8 comma-separated "euroc_pose" (vicon0), 8 blank-separated "tum".
/// Anything else (or a file that cannot be read here) is "euroc", whose reader then names the
/// line and what it expected.
std::string PoseFileFormat(const std::string& path);

/// EuRoC/ASL IMU CSV and a pose file (PoseFileFormat).
Input ReadFileInput(const std::string& imu_path, const std::string& poses_path);

/// A pipeline's /imu, /ground_truth (any format: the poses are what is measured), /noise and
/// /gravity; its tasks are not run. Throws ConfigError naming the pipeline and /ground_truth
/// when it has none.
Input ReadPipelineInput(const std::string& pipeline_path);

}  // namespace imuconv::optimize
