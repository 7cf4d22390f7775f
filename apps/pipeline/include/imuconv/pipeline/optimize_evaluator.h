// The optimize task's solve (tasks/optimize.cpp), registered from above.
//
// imuconv optimize (apps/optimize, with Ceres) links this library, so the pipeline cannot link
// it: apps/optimize registers its solve here with SetOptimizeEvaluator (as apps/check does the
// check task's, check_evaluator.h). A program without it (built without Ceres, or a test linking
// the pipeline alone) still parses and checks an optimize task, and fails it, naming the task,
// only if it runs it.
#pragma once

#include <string>

#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/json_check.h"
#include "imuconv/registry.h"

namespace imuconv::pipeline {

/// The task's settings, as `imuconv optimize` takes them (docs/optimize.md).
struct OptimizeSettings {
  double keyframe_step = 0.0;
  std::string method = "manifold";
  std::string convention = "left";
  std::string residual = "gtsam";
  double pose_sigma_m = 0.01, pose_sigma_rad = 0.01;
  double reintegrate_gyro = 0.01, reintegrate_accel = 0.10;
  int max_rounds = 4;
  int max_iterations = 100;
};

/// Solves over every IMU sample and pose, returning the object `imuconv optimize --json` prints;
/// throws imuconv::Error (naming the setting) when the data or the settings cannot be used.
using OptimizeEvaluator = json (*)(const Registry& reg, const ImuData& imu,
                                   const GroundTruth& poses, const ImuNoise& noise,
                                   const Vec3& gravity, const OptimizeSettings& settings);
void SetOptimizeEvaluator(OptimizeEvaluator evaluator);
OptimizeEvaluator GetOptimizeEvaluator();

}  // namespace imuconv::pipeline
