// What imuconv experiment prints: the summary table with what the numbers mean, or one JSON
// object (schemas/experiment_output.schema.json).
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "experiments.h"

namespace imuconv::experiment {

/// A difference as the summary and the report print it: three significant digits, "%.2e".
std::string Sci(double x);

void PrintSummary(std::ostream& out, const Result& r);

/// The run's settings (not the thread count: the numbers do not depend on it) and every
/// comparison with its mean difference matrices, rows of numbers.
nlohmann::json ResultJson(const Result& r);

}  // namespace imuconv::experiment
