#include "nees_input.h"

#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/pipeline_data.h"

namespace imuconv::nees {

Input ReadEurocInput(const std::string& imu_path, const std::string& gt_path) {
  Input in;
  in.imu = pipeline::ReadEurocImu(imu_path);
  in.gt = pipeline::ReadEurocGroundTruth(gt_path, *in.imu.origin);
  return in;
}

Input ReadPipelineInput(const std::string& pipeline_path) {
  const pipeline::Pipeline p = pipeline::Pipeline::Load(pipeline_path);
  if (!p.has_ground_truth())
    throw pipeline::ConfigError(p.file(), {{"/ground_truth",
                                            "required key is missing: nees starts each window at "
                                            "the ground truth and compares its end with it"}});
  Input in;
  in.imu = pipeline::ReadPipelineImu(p);
  in.gt = *pipeline::ReadPipelineGroundTruth(p, in.imu);
  if (!in.gt.full_state)
    throw pipeline::ConfigError(p.file(), {{"/ground_truth/format",
                                            "nees needs the full state (format \"euroc\": "
                                            "velocity and biases), found \"" +
                                                in.gt.format + "\" (poses only)"}});
  in.gravity = pipeline::PipelineGravity(p);
  in.noise = pipeline::PipelineNoiseIfGiven(p);
  return in;
}

}  // namespace imuconv::nees
