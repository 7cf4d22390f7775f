// imuconv montecarlo's report page (pages.h).
#include <algorithm>
#include <cmath>
#include <limits>

#include "imuconv/check/difference.h"
#include "imuconv/chi_square.h"
#include "imuconv/report/chart.h"
#include "imuconv/report/heatmap.h"
#include "imuconv/report/markup.h"
#include "montecarlo.h"
#include "pages.h"

namespace imuconv::report {
namespace {

// The signed map's anchor: |z| up to 5 drawn, beyond it the end colour; tolerance 3, the
// per-entry two-sided 0.27 % level of a normal z (with the 120 distinct entries of a symmetric
// 15x15, about 0.3 beyond it by chance per report), so a cell in the failure colours is
// unlikely to be sampling.
constexpr double kSignedMax = 5.0, kSignedTolerance = 3.0;

// (S - Sigma) / its sampling standard deviation, entry by entry. S is the unbiased sample
// covariance of N Gaussian errors, (N - 1) S ~ Wishart(Sigma, N - 1), whose entries have
// var(S_ij) = (Sigma_ij^2 + Sigma_ii Sigma_jj) / (N - 1). An entry with no variance under Sigma
// (a zero row: a bias block a method does not propagate) is 0 when S agrees exactly and
// +-infinity when it does not.
Eigen::MatrixXd Standardized(const Mat15& sigma, const Mat15& s, int trials) {
  Eigen::MatrixXd z(15, 15);
  const double dof = static_cast<double>(std::max(trials - 1, 1));
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j) {
      const double sd = std::sqrt((sigma(i, j) * sigma(i, j) + sigma(i, i) * sigma(j, j)) / dof);
      const double diff = s(i, j) - sigma(i, j);
      z(i, j) =
          sd > 0.0
              ? diff / sd
              : (diff == 0.0 ? 0.0 : std::copysign(std::numeric_limits<double>::infinity(), diff));
    }
  return z;
}

// The trials' NEES in linear bins against the counts chi-square(15) predicts in each (its exact
// CDF, imuconv/chi_square.h), with the chi-square(15) mean and the 95 % per-trial bounds.
std::string TrialNeesHistogram(const std::vector<double>& nees) {
  constexpr int kBins = 30;
  constexpr double kDof = 15.0;
  // At least up to chi-square(15)'s 0.9999 quantile (about 44), so a consistent run's tail fits.
  double hi = ChiSquareQuantileExact(kDof, 0.9999);
  std::size_t finite = 0;
  for (double v : nees)
    if (std::isfinite(v)) {
      hi = std::max(hi, v);
      ++finite;
    }
  hi *= 1.0 + 1e-9;  // the largest value inside the last bin
  Bars bars{"trials", {}, std::vector<double>(kBins, 0.0), "#9ecae1"};
  for (int k = 0; k <= kBins; ++k) bars.edges.push_back(hi * k / kBins);
  for (double v : nees)
    if (std::isfinite(v))
      bars.heights[static_cast<std::size_t>(
          std::clamp(static_cast<int>(v / hi * kBins), 0, kBins - 1))] += 1.0;
  PointSeries expected{"expected under chi2(15)", {}, {}, "#d62728", true, 2.0};
  for (int k = 0; k < kBins; ++k) {
    const double a = bars.edges[static_cast<std::size_t>(k)],
                 b = bars.edges[static_cast<std::size_t>(k) + 1];
    expected.x.push_back(0.5 * (a + b));
    expected.y.push_back(static_cast<double>(finite) *
                         (ChiSquareCdf(kDof, b) - ChiSquareCdf(kDof, a)));
  }
  ChartSpec c;
  c.title = "Per-trial NEES against chi-square(15)";
  c.x.label = "NEES";
  c.x.min = 0.0;
  c.y.label = "trials per bin";
  c.bars.push_back(std::move(bars));
  c.series.push_back(std::move(expected));
  c.lines.push_back({"chi2(15) mean", kDof, true, "#2ca02c", false});
  c.lines.push_back({"chi2(15) 95 % bounds", ChiSquareQuantileExact(kDof, 0.025), true, "#d62728"});
  c.lines.push_back({"", ChiSquareQuantileExact(kDof, 0.975), true, "#d62728"});
  return ChartSvg(c);
}

}  // namespace

HtmlDocument MontecarloPage(const montecarlo::Result& r, const Inputs& inputs) {
  const montecarlo::Statistics& st = r.stats;
  HtmlDocument doc("imuconv montecarlo");
  std::string reason;
  for (const auto& x : r.reasons) reason += (reason.empty() ? "" : "; ") + x;
  doc.AddVerdict(r.verdict == montecarlo::Verdict::consistent, reason);
  doc.AddParagraph(std::string("Verdict: ") +
                   (r.verdict == montecarlo::Verdict::consistent ? "consistent" : "inconsistent") +
                   ".");
  doc.AddList(r.reasons);
  std::vector<std::vector<std::string>> input_rows;
  for (const auto& [role, path] : inputs) input_rows.push_back({role, path});
  doc.AddTable({"input", "file"}, input_rows);

  doc.AddHeading(2, "Summary");
  doc.AddTable(
      {"quantity", "value"},
      {{"method", r.method + " (" + r.method_kind + ")"},
       {"scored in", r.convention},
       {"trials, seed", std::to_string(r.trials) + ", " + std::to_string(r.seed)},
       {"samples, duration [s]", std::to_string(r.samples) + ", " + Readable(r.duration, 6)},
       {"noise model", r.noise_model.simulated +
                           (r.noise_model.matches ? "" : " (NOT the prediction's)") + ": " +
                           r.noise_model.note},
       {"relative Frobenius error |S - Sigma|_F / |Sigma|_F", Readable(st.relative_frobenius, 4)},
       {"NEES mean (expected 15)", Readable(st.nees_mean, 4) + ", " +
                                       Readable(100 * montecarlo::kNeesConfidence, 3) +
                                       " % bounds [" + Readable(st.nees_bounds[0], 4) + ", " +
                                       Readable(st.nees_bounds[1], 4) + "]"},
       {"KL divergence", Readable(st.kl, 4) + ", " + Readable(100 * montecarlo::kKlLevel, 3) +
                             " % bound " + Readable(st.kl_bound, 4)}});
  // Each axis's ratio S_ii / Sigma_ii has the sampling standard deviation sqrt(2 / (N - 1))
  // (the Wishart variance above with i = j); the band is 1 +- 2 of them.
  const double band = 2.0 * std::sqrt(2.0 / static_cast<double>(std::max(r.trials - 1, 1)));
  std::vector<std::vector<std::string>> block_rows;
  std::vector<std::string> labels;
  for (const auto& b : r.blocks) {
    labels.push_back(b.block);
    std::vector<std::string> row = {b.block, Readable(b.variance_ratio, 4)};
    int outside = 0;
    for (double a : b.axes) {
      const bool in = std::abs(a - 1.0) <= band;
      outside += in ? 0 : 1;
      row.push_back(Readable(a, 4) + (in ? "" : " (outside)"));
    }
    row.push_back(outside ? std::to_string(outside) + " of 3 axes outside" : "all inside");
    block_rows.push_back(row);
  }
  doc.AddTable({"block", "variance ratio (sample / predicted)", "x", "y", "z",
                "band 1 \u00b1 " + Readable(band, 3)},
               block_rows);
  doc.AddParagraph("The band is 1 \u00b1 2 sqrt(2 / (N - 1)) = [" + Readable(1.0 - band, 4) + ", " +
                   Readable(1.0 + band, 4) + "] for N = " + std::to_string(r.trials) +
                   ": each axis's ratio S_ii / Sigma_ii has the sampling standard deviation sqrt(2 "
                   "/ (N - 1)), so a "
                   "consistent method leaves about 1 axis in 20 outside it by chance.");

  doc.AddHeading(2, "Sample covariance against the predicted one");
  if (labels.size() == 5) {
    // The sampling error alone: the sample covariance's entry on the correlation scale has a
    // standard deviation of sqrt((1 + rho^2) / (N - 1)), between 1 and sqrt(2) times 1/sqrt(N - 1);
    // the correlation map's tolerance is 3 of the larger.
    const double sampling = 1.0 / std::sqrt(static_cast<double>(std::max(r.trials - 1, 1)));
    HeatmapSpec z;
    z.values = Standardized(r.predicted, st.sample_cov, r.trials);
    z.row_blocks = z.col_blocks = labels;
    z.title = "Standardized: (S - Sigma) / sd(S)";
    z.value_name = "z";
    z.anchored = AnchoredScale::Signed(kSignedMax, kSignedTolerance);
    HeatmapSpec corr;
    corr.values = check::CorrelationScaleEntries(r.predicted, st.sample_cov);
    corr.row_blocks = corr.col_blocks = labels;
    corr.title = "Correlation scale: |S - Sigma| / sqrt(Sigma_ii Sigma_jj)";
    // From 1e-6 (far below any sampling error of a run that fits in memory) to 10 (an order of
    // magnitude off), the tolerance 3 sqrt(2) / sqrt(N - 1).
    corr.anchored =
        AnchoredScale::Magnitude(1e-6, 1e1, std::min(3.0 * std::sqrt(2.0) * sampling, 5.0));
    doc.AddFigures(
        {{HeatmapSvg(z),
          "z_ij = (S_ij - Sigma_ij) / sqrt((Sigma_ij^2 + Sigma_ii Sigma_jj) / (N - 1)), S the "
          "sample "
          "covariance of the " +
              std::to_string(r.trials) + " end errors, Sigma the predicted one, in " +
              r.convention +
              "'s block order: the Wishart sampling standard deviation of each entry. Red: S "
              "larger "
              "than Sigma predicts, violet: smaller; beyond \u00b13 (0.27 % per entry by chance) "
              "the colours turn dark. An entry with no variance under Sigma is 0 where S agrees "
              "exactly."},
         {HeatmapSvg(corr),
          "The same differences on the correlation scale. Sampling alone gives about " +
              Readable(sampling, 2) + " to " + Readable(std::sqrt(2.0) * sampling, 2) +
              " (1 to sqrt(2) times 1/sqrt(N - 1)); the tolerance is 3 times the larger. A dot: "
              "exactly 0 (S and Sigma agree, e.g. both zero)."}});
  } else {
    doc.AddParagraph("No block labels in the result: the heatmaps are left out.");
  }
  if (!r.trial_nees.empty()) {
    doc.AddHeading(2, "Per-trial NEES");
    doc.AddFigures({{TrialNeesHistogram(r.trial_nees),
                     "Each trial's NEES e^T Sigma^-1 e (" + std::to_string(r.trial_nees.size()) +
                         " trials) in 30 bins against the counts chi-square(15) predicts: a "
                         "consistent method's "
                         "histogram follows the curve. Too far right: Sigma too small; too far "
                         "left: too large. "
                         "The verdict tests their mean (" +
                         Readable(st.nees_mean, 4) + ")."}});
  }
  return doc;
}

}  // namespace imuconv::report
