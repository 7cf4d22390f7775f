// imuconv check as the pipeline's check task (apps/pipeline/src/tasks/check.cpp): the pipeline
// knows the task's grammar and input, and this library, which links the pipeline, supplies the
// evaluation (imuconv/pipeline/check_evaluator.h; the direction is in docs/map.md).
#pragma once

#include <cstdint>
#include <optional>

#include "imuconv/check/case_input.h"

namespace imuconv::pipeline {
class Pipeline;
}

namespace imuconv::check {

/// Makes the pipeline's check tasks run imuconv check (RunCheck, ReportJson). Idempotent;
/// the imuconv command calls it when it registers `check`.
void RegisterPipelineTask();

/// The samples (all of them, read as `imuconv run` reads /imu) and the /noise of a pipeline,
/// with the data's time origin in nanoseconds (nothing for inline samples without one): the
/// input of `imuconv check --pipeline`. Throws ConfigError naming the pipeline and /imu or
/// /noise when it has none, ReadError for the data file's problems.
CaseInput ReadPipelineInput(const pipeline::Pipeline& p, std::optional<std::int64_t>& origin_ns);

}  // namespace imuconv::check
