// The pipeline's IMU samples read whole from its parsed form (spec_data.h).
#include "spec_data.h"

#include <algorithm>

#include "imuconv/pipeline/imu_plausibility.h"
#include "imuconv/pipeline/sample_checks.h"
#include "pipeline_spec.h"

namespace imuconv::pipeline {

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
      throw ConfigError(
          s.file, {{src.pointer + "/samples/" + std::to_string(src.inline_index[i]) + "/0",
                    "time is too close to the previous sample's to be told apart in seconds"}});
    imu.samples.push_back(smp);
  }
  if (src.csv.time_origin) imu.origin = o;
  imu.warnings = ImuPlausibilityWarnings(imu.samples, s.file + ": " + src.pointer + "/samples");
  return imu;
}

void CheckImuAgainstKnownData(const PipelineSpec& s, const ImuData& imu, const GroundTruth* gt) {
  if (!s.imu || imu.samples.size() < 2) return;
  if (s.has_noise) {
    double shortest = imu.samples[1].t - imu.samples[0].t;
    for (std::size_t k = 2; k < imu.samples.size(); ++k)
      shortest = std::min(shortest, imu.samples[k].t - imu.samples[k - 1].t);
    if (const auto issue = FindNoiseIssue(s.noise, shortest))
      throw ConfigError(s.file,
                        {{"/noise", (s.noise_file.empty() ? "" : s.noise_file + ": ") + *issue}});
  }
  if (!gt || gt->t.size() < 2) return;
  std::vector<double> t(imu.samples.size());
  for (std::size_t k = 0; k < t.size(); ++k) t[k] = imu.samples[k].t;
  const bool euroc = s.imu->format == ImuSourceSpec::Format::Euroc;
  const auto issue = FindRateDisagreement(MedianPeriod(t), MedianPeriod(gt->t),
                                          euroc ? TimeUnit::ns : s.imu->csv.time_unit,
                                          euroc ? TimeSource::imu_euroc : TimeSource::imu);
  if (issue)
    throw ConfigError(
        s.file,
        {{s.imu->pointer + (euroc || s.imu->csv.time_unit == TimeUnit::s ? "" : "/time_unit"),
          "IMU " + imu.source + " against ground truth " + gt->source + ": " + *issue}});
}

ImuData ReadSpecImu(const PipelineSpec& s) {
  if (!s.imu)
    throw ConfigError(s.file,
                      {{"/imu", "required key is missing: the IMU samples are read from it"}});
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
    throw ReadError(
        imu.source, 0,
        "has " + std::to_string(imu.samples.size()) + " IMU sample(s); at least 2 are needed");
  CheckImuAgainstKnownData(s, imu, nullptr);  // the noise; the ground truth when it is read
  return imu;
}

}  // namespace imuconv::pipeline
