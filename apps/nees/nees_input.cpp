#include "nees_input.h"

#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/pipeline/kalibr_yaml.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/pipeline_data.h"
#include "imuconv/printable.h"
#include "imuconv/registry.h"

namespace imuconv::nees {

namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

ImuNoise ReadNoiseFile(const std::string& path) {
  if (EndsWith(path, ".yaml") || EndsWith(path, ".yml"))
    return pipeline::data::ReadKalibrImuYaml(path);
  return pipeline::ReadJsonFileAs(path, [](const pipeline::Node& root) {
    if (root.has("noise")) return pipeline::NoiseFromJson(root["noise"]);
    return pipeline::NoiseFromJson(root);
  });
}

ImuNoise NoiseGivenOrInPipeline(const std::string& noise_path,
                                const std::optional<ImuNoise>& pipeline_noise,
                                const std::string& pipeline_path) {
  if (!noise_path.empty()) return ReadNoiseFile(noise_path);
  if (pipeline_noise) return *pipeline_noise;
  throw Error(Printable(pipeline_path) + ": /noise: required key is missing (or give --noise)");
}

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
