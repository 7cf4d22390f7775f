#include "imuconv/optimize/pipeline_task.h"

#include "imuconv/optimize/optimize.h"
#include "imuconv/optimize/optimize_output.h"
#include "imuconv/pipeline/optimize_evaluator.h"

namespace imuconv::optimize {
namespace {

pipeline::json Evaluate(const Registry& reg, const pipeline::ImuData& imu,
                        const pipeline::GroundTruth& poses, const ImuNoise& noise,
                        const Vec3& gravity, const pipeline::OptimizeSettings& s) {
  Options o;
  o.keyframe_step = s.keyframe_step;
  o.method = s.method;
  o.convention = s.convention;
  o.kind = s.residual == "forster" ? ResidualKind::Forster : ResidualKind::Gtsam;
  o.pose_sigma_m = s.pose_sigma_m;
  o.pose_sigma_rad = s.pose_sigma_rad;
  o.reintegrate_gyro = s.reintegrate_gyro;
  o.reintegrate_accel = s.reintegrate_accel;
  o.max_rounds = s.max_rounds;
  o.max_iterations = s.max_iterations;
  o.noise = noise;
  o.gravity = gravity;
  return ResultJson(RunOptimize(reg, imu, poses, o));
}

}  // namespace

void RegisterPipelineTask() { pipeline::SetOptimizeEvaluator(&Evaluate); }

}  // namespace imuconv::optimize
