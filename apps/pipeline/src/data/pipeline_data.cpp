// A pipeline's data outside a run (imuconv/pipeline/pipeline_data.h).
#include "imuconv/pipeline/pipeline_data.h"

#include "../spec.h"
#include "imuconv/pipeline/imu_plausibility.h"
#include "spec_data.h"

namespace imuconv::pipeline {
namespace {

CheckEvaluator g_check_evaluator = nullptr;

}  // namespace

ImuData InlineImu(const PipelineSpec& s) {
  const ImuSourceSpec& src = *s.imu;
  TimeOrigin o;
  o.unit = src.csv.time_unit;
  if (src.csv.time_origin) o.value = *src.csv.time_origin;
  ImuData imu;
  imu.source = "inline";
  for (std::size_t i = 0; i < src.inline_raw.size(); ++i) {
    ImuSample smp = src.inline_raw[i];
    smp.t = o.relative_seconds(src.inline_t[i]);
    if (!imu.samples.empty() && !(smp.t > imu.samples.back().t))
      throw ConfigError(s.file, {{src.pointer + "/samples/" + std::to_string(src.inline_index[i]) + "/0",
                                  "time is too close to the previous sample's to be told apart in seconds"}});
    imu.samples.push_back(smp);
  }
  if (src.csv.time_origin) imu.origin = o;
  imu.warnings = ImuPlausibilityWarnings(imu.samples, s.file + ": " + src.pointer + "/samples");
  return imu;
}

ImuData ReadPipelineImu(const Pipeline& p) { return ReadSpecImu(p.spec()); }

ImuData ReadSpecImu(const PipelineSpec& s) {
  if (!s.imu) throw ConfigError(s.file, {{"/imu", "required key is missing: the IMU samples are read from it"}});
  ReadOptions ro;
  ro.timing = s.imu->timing;
  ImuData imu;
  switch (s.imu->format) {
    case ImuSourceSpec::Format::Euroc:
      imu = ReadEurocImu(s.imu->path, s.imu->origin_ns, ro);
      break;
    case ImuSourceSpec::Format::Csv:
      imu = ReadCsvImu(s.imu->path, s.imu->csv, ro);
      break;
    case ImuSourceSpec::Format::Inline:
      imu = InlineImu(s);
      break;
  }
  if (imu.samples.size() < 2)
    throw ReadError(imu.source, 0,
                    "has " + std::to_string(imu.samples.size()) + " IMU sample(s); at least 2 are needed");
  return imu;
}

std::optional<GroundTruth> ReadPipelineGroundTruth(const Pipeline& p, const ImuData& imu) {
  const PipelineSpec& s = p.spec();
  if (!s.gt) return std::nullopt;
  TimeOrigin o;
  if (imu.origin)
    o = *imu.origin;
  else
    o.unit = TimeUnit::s;  // inline samples without an origin: stamps taken as absolute (as a run does)
  ReadOptions ro;
  ro.timing = s.gt->timing;
  return s.gt->format == "euroc" ? ReadEurocGroundTruth(s.gt->path, o, ro)
                                 : ReadPoseGroundTruth(s.gt->path, s.gt->format, o, ro, s.gt->sensor);
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

void SetCheckEvaluator(CheckEvaluator evaluator) { g_check_evaluator = evaluator; }
CheckEvaluator GetCheckEvaluator() { return g_check_evaluator; }

}  // namespace imuconv::pipeline
