// The inputs of imuconv nees: the IMU samples, the full-state ground truth on their time axis,
// and (from a pipeline) the noise and gravity. Either EuRoC/ASL files, or a pipeline file whose
// /imu (EuRoC, generic CSV with its column map, time unit and origin, or inline samples),
// /ground_truth and /noise are read as `imuconv run` reads them (imuconv/pipeline/pipeline_data.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "imuconv/pipeline/imu_reader.h"

namespace imuconv::nees {

struct Input {
  pipeline::ImuData imu;
  pipeline::GroundTruth gt;
  std::optional<ImuNoise> noise;  ///< the pipeline's /noise, when it has one
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  /// The samples' suspected units or column order (imu.warnings), then the ground truth's
  /// rotations against the gyro (pipeline::PoseGyroWarnings).
  std::vector<std::string> warnings;
};

/// The four noise densities from --noise: a Kalibr imu.yaml (by extension, .yaml/.yml in any
/// case), else a JSON file holding a pipeline's "noise" object, or a whole pipeline whose /noise
/// is one, in either form the pipeline takes (the densities, or {"kalibr": "imu.yaml"} relative
/// to that JSON file's directory; pipeline::NoiseFormFromJson, the pipeline's own reader). The
/// readers' errors name the file and the line or JSON pointer. (nees and optimize take --noise
/// alike.)
ImuNoise ReadNoiseFile(const std::string& path);

/// The noise densities nees and optimize use: --noise's file when given (ReadNoiseFile), else
/// the pipeline's /noise (`pipeline_noise`). Throws imuconv::Error naming the pipeline and
/// /noise when it has none. Each command refuses a call with neither --noise nor --pipeline as
/// a usage error before it reads anything.
ImuNoise NoiseGivenOrInPipeline(const std::string& noise_path,
                                const std::optional<ImuNoise>& pipeline_noise,
                                const std::string& pipeline_path);

/// EuRoC/ASL IMU and full-state ground truth (ReadEurocImu, ReadEurocGroundTruth).
Input ReadEurocInput(const std::string& imu_path, const std::string& gt_path);

/// A pipeline's /imu, /ground_truth, /noise and /gravity (its tasks are not run). Throws
/// ConfigError naming the pipeline and the pointer when it has no /ground_truth, or one that
/// is poses only (a window starts from the ground truth's velocity and biases too).
Input ReadPipelineInput(const std::string& pipeline_path);

}  // namespace imuconv::nees
