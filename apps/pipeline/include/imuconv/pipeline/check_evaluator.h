// The check task's evaluation (tasks/check.cpp), registered from above.
//
// The evaluation lives above the pipeline (apps/check links imuconv_pipeline, so the pipeline
// cannot link it): apps/check registers it here with SetCheckEvaluator, and a program that
// never does (a test linking the pipeline alone) still parses and checks a check task, and
// fails it, naming the task, only if it runs it. The direction is in docs/map.md.
#pragma once

#include <string>
#include <vector>

#include "imuconv/pipeline/json_check.h"
#include "imuconv/pipeline/registered_from_above.h"
#include "imuconv/registry.h"
#include "imuconv/types.h"

namespace imuconv::pipeline {

struct DeclaredMeasurement;  // forms/measurement.h

/// What the check task hands to imuconv check: every IMU sample of the pipeline, its noise,
/// the measurements as declared (times on the pipeline's time axis) and the file they came
/// from. The evaluator returns the object `imuconv check --json` prints (verdict, tolerances,
/// measurements) and whether the verdict is consistent; it throws ConfigError naming the
/// measurements file and pointer when a measurement cannot be checked.
struct CheckEvaluation {
  json report;
  bool consistent = true;
};
using CheckEvaluator = CheckEvaluation (*)(const Registry& reg,
                                           const std::vector<ImuSample>& samples,
                                           const ImuNoise& noise,
                                           const std::vector<DeclaredMeasurement>& ms,
                                           const std::string& measurements_file);
inline void SetCheckEvaluator(CheckEvaluator evaluator) {
  RegisteredFromAbove<CheckEvaluator>() = evaluator;
}
inline CheckEvaluator GetCheckEvaluator() { return RegisteredFromAbove<CheckEvaluator>(); }

}  // namespace imuconv::pipeline
