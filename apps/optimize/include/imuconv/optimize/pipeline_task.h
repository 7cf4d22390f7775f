// The pipeline's optimize task (apps/pipeline/src/tasks/optimize.cpp) solves with this library:
// RegisterPipelineTask() hands it the solve (imuconv/pipeline/optimize_evaluator.h). The
// command line and the Python module call it once.
#pragma once

namespace imuconv::optimize {

void RegisterPipelineTask();

}  // namespace imuconv::optimize
