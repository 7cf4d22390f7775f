// The pipeline's IMU samples read whole from its parsed form (internal to imuconv_pipeline;
// the public face is imuconv/pipeline/pipeline_data.h).
#pragma once

#include "imuconv/pipeline/imu_reader.h"

namespace imuconv::pipeline {

struct PipelineSpec;

/// Inline samples (/imu/samples; timing checked when parsed, at their pointers) on their time
/// axis: the same origin as a CSV's, and two times that round to one second value refused.
ImuData InlineImu(const PipelineSpec& s);

/// Every sample of /imu (no time range left out), as the run's load stage reads it.
ImuData ReadSpecImu(const PipelineSpec& s);

}  // namespace imuconv::pipeline
