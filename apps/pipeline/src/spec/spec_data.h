// The pipeline's IMU samples read whole from its parsed form (internal to imuconv_pipeline;
// the public face, from a loaded Pipeline, is imuconv/pipeline/pipeline_data.h).
#pragma once

#include "imuconv/pipeline/imu_reader.h"

namespace imuconv::pipeline {

struct PipelineSpec;

/// Inline samples (/imu/samples; timing checked when parsed, at their pointers) on their time
/// axis: the same origin as a CSV's, and two times that round to one second value refused.
ImuData InlineImu(const PipelineSpec& s);

/// Every sample of /imu (no time range left out), as the run's load stage reads it.
ImuData ReadSpecImu(const PipelineSpec& s);

/// What the IMU samples are checked against once the rest of the data is known (the checks
/// of imuconv/pipeline/sample_checks.h): the noise against the shortest sample period, and
/// the IMU's rate against the ground truth's (a wrong time_unit). ConfigError at /noise or
/// /imu naming both files. Called by the run's load stage and by ReadPipelineGroundTruth.
void CheckImuAgainstKnownData(const PipelineSpec& s, const ImuData& imu, const GroundTruth* gt);

}  // namespace imuconv::pipeline
