// imuconv montecarlo's report page (pages.h).
#include <algorithm>
#include <cmath>

#include "check/difference.h"
#include "imuconv/report/heatmap.h"
#include "imuconv/report/markup.h"
#include "montecarlo.h"
#include "report/pages/pages.h"

namespace imuconv::report {

HtmlDocument MontecarloPage(const montecarlo::Result& r, const Inputs& inputs) {
  const montecarlo::Statistics& st = r.stats;
  HtmlDocument doc("imuconv montecarlo");
  doc.AddParagraph(std::string("Verdict: ") +
                   (r.verdict == montecarlo::Verdict::consistent ? "consistent" : "inconsistent") + ".");
  doc.AddList(r.reasons);
  std::vector<std::vector<std::string>> input_rows;
  for (const auto& [role, path] : inputs) input_rows.push_back({role, path});
  doc.AddTable({"input", "file"}, input_rows);

  doc.AddHeading(2, "Summary");
  doc.AddTable({"quantity", "value"},
               {{"method", r.method + " (" + r.method_kind + ")"},
                {"scored in", r.convention},
                {"trials, seed", std::to_string(r.trials) + ", " + std::to_string(r.seed)},
                {"samples, duration [s]", std::to_string(r.samples) + ", " + Readable(r.duration, 6)},
                {"noise model", r.noise_model.simulated + (r.noise_model.matches ? "" : " (NOT the prediction's)") +
                                    ": " + r.noise_model.note},
                {"relative Frobenius error |S - Sigma|_F / |Sigma|_F", Readable(st.relative_frobenius, 4)},
                {"NEES mean (expected 15)", Readable(st.nees_mean, 4) + ", " +
                                                Readable(100 * montecarlo::kNeesConfidence, 3) + " % bounds [" +
                                                Readable(st.nees_bounds[0], 4) + ", " +
                                                Readable(st.nees_bounds[1], 4) + "]"},
                {"KL divergence", Readable(st.kl, 4) + ", " + Readable(100 * montecarlo::kKlLevel, 3) +
                                      " % bound " + Readable(st.kl_bound, 4)}});
  std::vector<std::vector<std::string>> block_rows;
  std::vector<std::string> labels;
  for (const auto& b : r.blocks) {
    labels.push_back(b.block);
    block_rows.push_back({b.block, Readable(b.variance_ratio, 4), Readable(b.axes[0], 4), Readable(b.axes[1], 4),
                          Readable(b.axes[2], 4)});
  }
  doc.AddTable({"block", "variance ratio (sample / predicted)", "x", "y", "z"}, block_rows);

  doc.AddHeading(2, "Sample covariance against the predicted one");
  if (labels.size() == 5) {
    // The sampling error alone: the sample covariance's entry on the correlation scale has a
    // standard deviation of sqrt((1 + rho^2) / (N - 1)), between 1 and sqrt(2) times 1/sqrt(N - 1).
    const double sampling = 1.0 / std::sqrt(static_cast<double>(std::max(r.trials - 1, 1)));
    HeatmapSpec corr;
    corr.values = check::CorrelationScaleEntries(r.predicted, st.sample_cov);
    corr.row_blocks = corr.col_blocks = labels;
    corr.title = "Correlation scale: |S - Sigma| / sqrt(Sigma_ii Sigma_jj)";
    HeatmapSpec rel;
    rel.values = check::RelativeAboveFloorEntries(r.predicted, st.sample_cov);
    rel.row_blocks = rel.col_blocks = labels;
    rel.title = "Relative: |S - Sigma| / max(|Sigma|, 1e-4 max|Sigma|)";
    doc.AddFigures(
        {{HeatmapSvg(corr), "S the sample covariance of the " + std::to_string(r.trials) +
                                " end errors, Sigma the predicted covariance, in " + r.convention +
                                "'s block order. Sampling alone gives about " + Readable(sampling, 2) + " to " +
                                Readable(std::sqrt(2.0) * sampling, 2) + " (1 to sqrt(2) times 1/sqrt(N - 1))."},
         {HeatmapSvg(rel), "The same entries relative to Sigma's own (above a floor of 1e-4 of its largest): "
                           "off-diagonal entries near zero are noisy here by construction."}});
  } else {
    doc.AddParagraph("No block labels in the result: the heatmaps are left out.");
  }
  return doc;
}

}  // namespace imuconv::report
