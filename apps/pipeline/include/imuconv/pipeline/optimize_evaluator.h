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
#include "imuconv/pipeline/registered_from_above.h"
#include "imuconv/registry.h"

namespace imuconv::pipeline {

/// The smallest pose standard deviation optimize takes, in metres and in radians alike. Its
/// residual is whitened by 1 / sigma, so the cost carries 1 / sigma^2: at 1e-300 that is inf
/// and the cost NaN; at 1e-100 the poses' information (1e200) swamps the IMU factors' beyond
/// double precision and the covariance comes out rank deficient. 1 nm and 1 nrad are a thousand
/// times finer than the digits pose files hold (EuRoC's ground truth: 1e-6 m) and still solve
/// with full covariances (the V1_01 slice at 0.5 s keyframes), so no meaningful sigma is below.
inline constexpr double kMinPoseSigma = 1e-9;
inline const char* const kMinPoseSigmaText = "1e-9";

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
inline void SetOptimizeEvaluator(OptimizeEvaluator evaluator) {
  RegisteredFromAbove<OptimizeEvaluator>() = evaluator;
}
inline OptimizeEvaluator GetOptimizeEvaluator() { return RegisteredFromAbove<OptimizeEvaluator>(); }

}  // namespace imuconv::pipeline
