// The two forms of a check's result: one JSON object (--json; schemas/check_output.schema.json)
// and a short table for a person.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>

#include "imuconv/check/check.h"

namespace imuconv::check {

nlohmann::json ReportJson(const CheckResult& r);

void PrintTable(std::ostream& out, const CheckResult& r);

}  // namespace imuconv::check
