// The two faces of a montecarlo result: one JSON object (schemas/montecarlo_output.schema.json)
// and a human summary.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>

#include "montecarlo.h"

namespace imuconv::montecarlo {

nlohmann::json ReportJson(const Result& r);
void PrintSummary(std::ostream& out, const Result& r);

}  // namespace imuconv::montecarlo
