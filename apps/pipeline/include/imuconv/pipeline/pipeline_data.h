// A pipeline's data outside a run: its IMU samples, ground truth, noise and gravity, read as
// `imuconv run` reads them (format, CSV column map, time unit and origin, timing policy), for
// the commands that take their inputs from a pipeline file (`imuconv check --pipeline`,
// `imuconv nees --pipeline`); the check task reads the same from the parsed form
// (src/spec/spec_data.h). The check task's evaluator, registered from above, is in
// check_evaluator.h (included here: the commands that read a pipeline's data register it).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "imuconv/pipeline/check_evaluator.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/pipeline.h"

namespace imuconv::pipeline {

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

}  // namespace imuconv::pipeline
