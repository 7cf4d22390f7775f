// The pipeline's IMU samples read whole from its parsed form (internal to imuconv_pipeline;
// the public face is imuconv/pipeline/pipeline_data.h).
#pragma once

#include "imuconv/pipeline/imu_reader.h"

namespace imuconv::pipeline {

struct PipelineSpec;

/// Every sample of /imu (no time range left out), as the run's load stage reads it.
ImuData ReadSpecImu(const PipelineSpec& s);

}  // namespace imuconv::pipeline
