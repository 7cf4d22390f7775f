#include "imuconv/check/pipeline_task.h"

#include "imuconv/check/check.h"
#include "imuconv/check/report.h"
#include "imuconv/pipeline/pipeline_data.h"

namespace imuconv::check {
namespace {

pipeline::CheckEvaluation Evaluate(const Registry& reg, const std::vector<ImuSample>& samples,
                                   const ImuNoise& noise,
                                   const std::vector<pipeline::DeclaredMeasurement>& ms,
                                   const std::string& measurements_file) {
  CaseInput input;
  input.samples = samples;
  input.noise = noise;
  input.source = "the pipeline's IMU samples";
  const CheckResult r = RunCheck(reg, input, ms, measurements_file);
  return {ReportJson(r), r.verdict == Verdict::consistent};
}

}  // namespace

void RegisterPipelineTask() { pipeline::SetCheckEvaluator(&Evaluate); }

CaseInput ReadPipelineInput(const pipeline::Pipeline& p, std::optional<std::int64_t>& origin_ns) {
  const pipeline::ImuData imu = pipeline::ReadPipelineImu(p);
  CaseInput k;
  k.noise = pipeline::PipelineNoise(p, "imuconv check integrates the IMU samples with it");
  k.samples = imu.samples;
  k.source = "the pipeline's IMU samples";
  origin_ns = imu.origin ? imu.origin->nanoseconds() : std::nullopt;
  return k;
}

}  // namespace imuconv::check
