#include "experiment_report.h"

#include <cstdio>
#include <string>
#include <vector>

#include "imuconv/report/color_scale.h"
#include "imuconv/report/heatmap.h"
#include "imuconv/report/markup.h"
#include "summary.h"

namespace imuconv::experiment {
namespace {

std::string What(const Comparison& c) {
  if (c.matrix == "J_bias") return "bias Jacobian";
  if (c.matrix == "Phi") return "transition matrix Phi";
  return c.experiment == "preint-by-prop" ? "preintegrated covariance" : "propagated covariance";
}

/// One figure of the note: the comparisons of one experiment, each matrix kind (the two
/// schemes) on one colour scale so manifold and tangent read alike.
void AddFigure(report::HtmlDocument& doc, const Result& r, const std::string& experiment) {
  std::vector<std::vector<std::string>> rows;
  for (const Comparison& c : r.comparisons)
    if (c.experiment == experiment)
      rows.push_back({c.matrix, c.preintegrator, c.chart, Sci(c.note_mean), Sci(c.note_max),
                      Sci(c.scaled_mean), Sci(c.scaled_max),
                      c.scaled_metric == "correlation" ? "correlation scale" : "relative"});
  doc.AddTable({"matrix", "scheme", "chart", "note d mean", "note d max", "scaled d mean",
                "scaled d max", "scaled d"},
               rows);
  std::vector<report::HtmlDocument::Figure> figures;
  for (const Comparison& c : r.comparisons) {
    if (c.experiment != experiment) continue;
    std::vector<double> values;
    for (const Comparison& o : r.comparisons)
      if (o.experiment == experiment && o.matrix == c.matrix)
        values.insert(values.end(), o.mean_note_d.data(),
                      o.mean_note_d.data() + o.mean_note_d.size());
    report::HeatmapSpec spec;
    spec.values = c.mean_note_d;
    spec.row_blocks = c.row_blocks;
    spec.col_blocks = c.col_blocks;
    spec.title = What(c) + ", " + c.preintegrator;
    spec.value_name = "mean d";
    spec.scale = report::LogColorScale::Fit(values);
    figures.push_back({report::HeatmapSvg(spec), What(c) + ": " + c.preintegrator + " against " +
                                                     c.reference + " (the reference), in " +
                                                     c.chart + "; mean note d " + Sci(c.note_mean) +
                                                     ", max " + Sci(c.note_max)});
  }
  doc.AddFigures(figures);
}

}  // namespace

report::HtmlDocument ExperimentPage(const Result& r) {
  const Options& o = r.options;
  report::HtmlDocument doc("imuconv experiment: the note's Figures 1 and 2");
  doc.AddParagraph(
      std::to_string(o.trials) + " random trials of " + report::Readable(o.spec.duration_s, 6) +
      " s at " + report::Readable(o.spec.rate_hz, 6) + " Hz, seed " + std::to_string(o.seed) +
      "; propagator " + o.propagator + " on the samples" +
      (o.propagator_substeps > 1 ? " (" + std::to_string(o.propagator_substeps) + " knots per step)"
                                 : "") +
      "; preintegrators manifold and tangent (GTSAM's schemes) on GTSAM's " +
      (o.input == PreintegratorInput::mid ? "mid-sample" : "zero-order-hold") + " input.");
  doc.AddParagraph(
      "Each heatmap is the note's entrywise difference d = |r - e| / |r| where |r| > 1e-4, else |r "
      "- e| (r the "
      "reference), averaged over the trials, one cell per entry, its colour the decade of the "
      "value. The table also "
      "gives imuconv check's scale-aware d (a covariance on the correlation scale, other matrices "
      "relative above "
      "1e-4 of their largest entry), which weighs the tiny bias blocks at their own scale.");
  if (o.preint_by_prop) {
    doc.AddHeading(2, "Figure 1: preintegration by propagation");
    doc.AddParagraph(
        "The bias Jacobian and the covariance of " + o.propagator +
        " preintegration by propagation (the note, section 3.1), against GTSAM's numbers (the "
        "reference), in GTSAM's own charts.");
    AddFigure(doc, r, "preint-by-prop");
  }
  if (o.prop_by_preint) {
    doc.AddHeading(2, "Figure 2: propagation by preintegration");
    doc.AddParagraph(
        "Phi and the propagated covariance from each preintegrator's measurement (the note, "
        "section "
        "3.2, eq. prop-cov), against " +
        o.propagator +
        " propagation (the reference) from the trial's random state and covariance, in "
        "the left error state.");
    AddFigure(doc, r, "prop-by-preint");
  }
  doc.AddHeading(2, "Why the differences are not zero");
  doc.AddParagraph(
      "The two sides discretise the same equations differently: rk4 integrates the linearly "
      "interpolated samples to "
      "fourth order, GTSAM's schemes hold the mid value over each step, keep the rotation of the "
      "start of the step "
      "for p and v and take the noise as sigma^2/dt per step, which is first order. Doubling the "
      "rate halves every "
      "difference; halving rk4's own step changes none; a propagator of GTSAM's manifold scheme "
      "(--propagator openvins_discrete) leaves only rounding in the manifold comparisons "
      "(docs/experiment.md).");
  return doc;
}

}  // namespace imuconv::experiment
