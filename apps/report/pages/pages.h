// Each command's HTML report page, built from its result with the report library
// (imuconv/report/): check's per-measurement heatmaps of the entrywise differences under the
// best explanation, montecarlo's heatmaps of the sample covariance against the predicted one
// (standardized, signed) and its variance ratios against their band, each heatmap on a scale
// anchored to its kind and tolerance (anchored_scale.h) and each verdict a badge at the top;
// nees's NEES per window against chi-square(9), its two factors and offset flags, and each error
// component with its ±3 sigma.
// The command lines are apps/cmd_{check,montecarlo,nees}.cpp; docs/{check,montecarlo,nees}.md.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "imuconv/report/html_document.h"

namespace imuconv::check {
struct CheckResult;
}
namespace imuconv::montecarlo {
struct Result;
}
namespace imuconv::nees {
struct Result;
}

namespace imuconv::report {

/// What the page names as its inputs: (role, as given on the command line), e.g.
/// {"measurements", "meas.json"}.
using Inputs = std::vector<std::pair<std::string, std::string>>;

HtmlDocument CheckPage(const check::CheckResult& r, const Inputs& inputs);
HtmlDocument MontecarloPage(const montecarlo::Result& r, const Inputs& inputs);
/// Needs the result of a run with nees::Options::keep_errors for the error time series
/// (without, the page has the NEES figures only and says so).
HtmlDocument NeesPage(const nees::Result& r, const Inputs& inputs);

}  // namespace imuconv::report
