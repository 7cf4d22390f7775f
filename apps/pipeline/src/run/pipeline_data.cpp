// A pipeline's data outside a run (imuconv/pipeline/pipeline_data.h).
#include "imuconv/pipeline/pipeline_data.h"

#include "../spec/pipeline_spec.h"
#include "../spec/spec_data.h"

namespace imuconv::pipeline {

ImuData ReadPipelineImu(const Pipeline& p) { return ReadSpecImu(p.spec()); }

std::optional<GroundTruth> ReadPipelineGroundTruth(const Pipeline& p, const ImuData& imu) {
  const PipelineSpec& s = p.spec();
  if (!s.gt) return std::nullopt;
  TimeOrigin o;
  if (imu.origin)
    o = *imu.origin;
  else
    o.unit =
        TimeUnit::s;  // inline samples without an origin: stamps taken as absolute (as a run does)
  ReadOptions ro;
  ro.timing = s.gt->timing;
  GroundTruth gt = s.gt->format == "euroc"
                       ? ReadEurocGroundTruth(s.gt->path, o, ro)
                       : ReadPoseGroundTruth(s.gt->path, s.gt->format, o, ro, s.gt->sensor);
  CheckImuAgainstKnownData(s, imu, &gt);
  return gt;
}

ImuNoise PipelineNoise(const Pipeline& p, const std::string& why) {
  const PipelineSpec& s = p.spec();
  if (!s.has_noise) throw ConfigError(s.file, {{"/noise", "required key is missing: " + why}});
  return s.noise;
}

std::optional<ImuNoise> PipelineNoiseIfGiven(const Pipeline& p) {
  return p.spec().has_noise ? std::optional<ImuNoise>(p.spec().noise) : std::nullopt;
}

Vec3 PipelineGravity(const Pipeline& p) { return p.spec().gravity; }

}  // namespace imuconv::pipeline
