// imuconv experiment --report OUT.html: the note's Figures 1 and 2 as eight heatmaps of the
// mean entrywise difference d (the note's own d, averaged over the trials), with the table of
// means and maxima and what they mean, built with the report library (apps/report/).
#pragma once

#include "experiments.h"
#include "imuconv/report/html_document.h"

namespace imuconv::experiment {

report::HtmlDocument ExperimentPage(const Result& r);

}  // namespace imuconv::experiment
