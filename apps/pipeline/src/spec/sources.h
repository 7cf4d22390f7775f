// Reading the top-level "imu" and "ground_truth" sources of a pipeline document into their
// parsed forms (internal to imuconv_pipeline).
#pragma once

#include <optional>

#include "pipeline_spec.h"

namespace imuconv::pipeline {

/// The top-level "imu" and "ground_truth" sources.
std::optional<ImuSourceSpec> ReadImuSource(const ParseContext& ctx, const Node& n);
std::optional<GroundTruthSpec> ReadGroundTruthSource(const ParseContext& ctx, const Node& n);

}  // namespace imuconv::pipeline
