// A function the pipeline calls but a library above it provides (the direction is in
// docs/map.md): the check task's evaluation (check_evaluator.h, set by apps/check) and the
// optimize task's solve (optimize_evaluator.h, set by apps/optimize). Each has one slot,
// null until that library's RegisterPipelineTask sets it, so that a program that never does
// (a test linking the pipeline alone) still parses and checks such a task.
#pragma once

namespace imuconv::pipeline {

/// The slot of the function type `Function` (a function pointer): one per type.
template <typename Function>
Function& RegisteredFromAbove() {
  static Function function = nullptr;
  return function;
}

}  // namespace imuconv::pipeline
