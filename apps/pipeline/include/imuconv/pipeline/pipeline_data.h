// A pipeline's data outside a run: its IMU samples, ground truth, noise and gravity, read as
// `imuconv run` reads them (format, CSV column map, time unit and origin, timing policy), for
// the commands that take their inputs from a pipeline file (`imuconv check --pipeline`,
// `imuconv nees --pipeline`) and for the check task (tasks/check.cpp).
//
// The check task's evaluation lives above the pipeline (apps/check links imuconv_pipeline, so
// the pipeline cannot link it): apps/check registers it here with SetCheckEvaluator, and a
// program that never does (a test linking the pipeline alone) still parses and checks a check
// task, and fails it, naming the task, only if it runs it. The direction is in docs/map.md.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/pipeline.h"

namespace imuconv::pipeline {

struct DeclaredMeasurement;  // forms/measurement.h

/// Every IMU sample of the pipeline's /imu, with its time origin (no time range is left out).
/// Throws ConfigError at /imu when the pipeline has none, ReadError for the file's problems.
ImuData ReadPipelineImu(const Pipeline& p);

/// The pipeline's /ground_truth on `imu`'s time axis (every row), or nothing when it has none.
std::optional<GroundTruth> ReadPipelineGroundTruth(const Pipeline& p, const ImuData& imu);

/// The pipeline's /noise (given inline or as a Kalibr imu.yaml). Throws ConfigError at /noise
/// ("required key is missing: `why`") when it has none.
ImuNoise PipelineNoise(const Pipeline& p, const std::string& why);
/// The same, or nothing when the pipeline gives no /noise.
std::optional<ImuNoise> PipelineNoiseIfGiven(const Pipeline& p);

/// The pipeline's /gravity (its default when not given).
Vec3 PipelineGravity(const Pipeline& p);

/// What the check task hands to imuconv check: every IMU sample of the pipeline, its noise,
/// the measurements as declared (times on the pipeline's time axis) and the file they came
/// from. The evaluator returns the object `imuconv check --json` prints (verdict, tolerances,
/// measurements) and whether the verdict is consistent; it throws ConfigError naming the
/// measurements file and pointer when a measurement cannot be checked.
struct CheckEvaluation {
  json report;
  bool consistent = true;
};
using CheckEvaluator = CheckEvaluation (*)(const Registry& reg, const std::vector<ImuSample>& samples,
                                           const ImuNoise& noise, const std::vector<DeclaredMeasurement>& ms,
                                           const std::string& measurements_file);
void SetCheckEvaluator(CheckEvaluator evaluator);
CheckEvaluator GetCheckEvaluator();

}  // namespace imuconv::pipeline
