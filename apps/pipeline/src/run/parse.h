// Reading a pipeline document into its parsed form (internal to imuconv_pipeline): the
// top-level keys and sources (spec/), then each task by its kind's parser (tasks/kinds.cpp).
#pragma once

#include <memory>
#include <string>

#include "../spec/pipeline_spec.h"

namespace imuconv::pipeline {

/// Parses and validates the structure; throws ConfigError listing every issue.
std::unique_ptr<PipelineSpec> ParseSpec(const json& doc, const std::string& file,
                                        const std::string& base_dir);

}  // namespace imuconv::pipeline
