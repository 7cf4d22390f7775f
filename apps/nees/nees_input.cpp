#include "nees_input.h"

#include <cctype>
#include <filesystem>

#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/imu_plausibility.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/pipeline/kalibr_yaml.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/pipeline_data.h"
#include "imuconv/printable.h"
#include "imuconv/registry.h"

namespace imuconv::nees {

namespace {

// Whether `path`'s extension is .yaml or .yml, in any case (NOISE.YAML is a Kalibr file too).
bool IsYamlPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".yaml" || ext == ".yml";
}

// The samples' warnings, then the ground truth's against the gyro, named `gt_name`.
std::vector<std::string> JoinedWarnings(const pipeline::ImuData& imu,
                                        const pipeline::GroundTruth& gt,
                                        const std::string& gt_name) {
  std::vector<std::string> out = imu.warnings;
  for (auto& w : pipeline::PoseGyroWarnings(imu.samples, gt, gt_name)) out.push_back(std::move(w));
  return out;
}

}  // namespace

ImuNoise ReadNoiseFile(const std::string& path) {
  if (IsYamlPath(path)) return pipeline::data::ReadKalibrImuYaml(path);
  // A pipeline's /noise, or a noise object alone, in either form (inline or {"kalibr": ...}),
  // read by the pipeline's own reader; a Kalibr path is relative to this file's directory, as
  // Pipeline::Load resolves it.
  const std::string dir = std::filesystem::path(path).parent_path().string();
  const std::string base_dir = dir.empty() ? "." : dir;
  return pipeline::ReadJsonFileAs(path, [&](const pipeline::Node& root) {
    return pipeline::NoiseFormFromJson(root.has("noise") ? root["noise"] : root, base_dir);
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
  in.warnings = JoinedWarnings(in.imu, in.gt, gt_path);
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
  in.warnings = JoinedWarnings(in.imu, in.gt, p.file() + ": /ground_truth");
  return in;
}

}  // namespace imuconv::nees
