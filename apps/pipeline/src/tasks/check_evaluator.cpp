// The check task's evaluator, registered from above (imuconv/pipeline/check_evaluator.h).
#include "imuconv/pipeline/check_evaluator.h"

namespace imuconv::pipeline {
namespace {

CheckEvaluator g_check_evaluator = nullptr;

}  // namespace

void SetCheckEvaluator(CheckEvaluator evaluator) { g_check_evaluator = evaluator; }
CheckEvaluator GetCheckEvaluator() { return g_check_evaluator; }

}  // namespace imuconv::pipeline
