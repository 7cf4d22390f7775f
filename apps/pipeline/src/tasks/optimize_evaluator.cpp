// The optimize task's solve, registered from above (imuconv/pipeline/optimize_evaluator.h).
#include "imuconv/pipeline/optimize_evaluator.h"

namespace imuconv::pipeline {
namespace {

OptimizeEvaluator g_optimize_evaluator = nullptr;

}  // namespace

void SetOptimizeEvaluator(OptimizeEvaluator evaluator) { g_optimize_evaluator = evaluator; }
OptimizeEvaluator GetOptimizeEvaluator() { return g_optimize_evaluator; }

}  // namespace imuconv::pipeline
