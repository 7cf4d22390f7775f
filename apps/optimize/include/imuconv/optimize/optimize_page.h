// The --report page of imuconv optimize: the solve's summary, and each estimated bias component
// over time with its ±3 sigma band, against the poses file's biases where it has them.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "imuconv/optimize/optimize.h"
#include "imuconv/report/html_document.h"

namespace imuconv::optimize {

/// (role, path) of each input given, as the page lists them.
using PageInputs = std::vector<std::pair<std::string, std::string>>;

report::HtmlDocument OptimizePage(const Result& r, const PageInputs& inputs);

}  // namespace imuconv::optimize
