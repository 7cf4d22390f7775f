// The two faces of a nees result: one JSON object (schemas/nees_output.schema.json) and a
// human table.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "nees.h"

namespace imuconv::nees {

/// What an offset flag (error_components.h) commonly means, in words, for the table and the report.
extern const char* const kOffsetCauses;

nlohmann::json ReportJson(const Result& r);
/// One sentence per window length with windows skipped for reaching into a gap of the data
/// (none when there are none): the command's warnings, and a line of the table.
std::vector<std::string> SkippedWindows(const Result& r);
void PrintSummary(std::ostream& out, const Result& r);

}  // namespace imuconv::nees
