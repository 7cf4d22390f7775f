// imuconv nees's report page (pages.h).
#include <algorithm>
#include <cmath>

#include "imuconv/chi_square.h"
#include "imuconv/report/chart.h"
#include "imuconv/report/markup.h"
#include "nees.h"
#include "nees_report.h"
#include "pages.h"

namespace imuconv::report {
namespace {

constexpr int kHistogramBins = 30;
const char* const kBlocks[3] = {"p", "theta", "v"};
const char* const kAxes[3] = {"x", "y", "z"};
const char* const kUnits[3] = {"m", "rad", "m/s"};

// NEES of each window against its start time, on a log axis, with chi-square(9)'s bounds.
std::string NeesOverTime(const nees::Result& r, const nees::WindowLengthResult& w) {
  ChartSpec c;
  c.title = "NEES per window, " + Readable(w.length, 4) + " s windows";
  c.x.label = "window start [s]";
  c.y.label = "NEES";
  c.y.log = true;
  c.series.push_back({"NEES", w.t_start, w.nees, "#1f77b4", false, 2.0});
  c.lines.push_back({"chi2(9) " + Readable(100 * nees::kConfidence, 3) + " % bounds", r.chi2.lower,
                     false, "#d62728"});
  c.lines.push_back({"", r.chi2.upper, false, "#d62728"});
  c.lines.push_back({"chi2(9) median", r.chi2.median, false, "#2ca02c", false});
  return ChartSvg(c);
}

// Their histogram on log-spaced bins against the counts chi-square(9) predicts in each bin.
std::string NeesHistogram(const nees::Result& r, const nees::WindowLengthResult& w) {
  double lo = r.chi2.lower / 2.0, hi = r.chi2.upper * 2.0;
  for (double v : w.nees)
    if (std::isfinite(v) && v > 0.0) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  const double l0 = std::log10(lo),
               l1 = std::log10(hi) + 1e-9;  // the largest value inside the last bin
  Bars bars{"windows", {}, std::vector<double>(kHistogramBins, 0.0), "#9ecae1"};
  for (int k = 0; k <= kHistogramBins; ++k)
    bars.edges.push_back(std::pow(10.0, l0 + (l1 - l0) * k / kHistogramBins));
  std::size_t outside = 0;
  for (double v : w.nees) {
    if (!(std::isfinite(v) && v > 0.0)) {
      ++outside;
      continue;
    }
    const int k = std::clamp(static_cast<int>((std::log10(v) - l0) / (l1 - l0) * kHistogramBins), 0,
                             kHistogramBins - 1);
    bars.heights[static_cast<std::size_t>(k)] += 1.0;
  }
  PointSeries expected{"expected under chi2(9)", {}, {}, "#d62728", true, 2.0};
  const double n = static_cast<double>(w.nees.size() - outside);
  for (int k = 0; k < kHistogramBins; ++k) {
    const double a = bars.edges[static_cast<std::size_t>(k)],
                 b = bars.edges[static_cast<std::size_t>(k) + 1];
    expected.x.push_back(std::sqrt(a * b));
    expected.y.push_back(n * (ChiSquareCdf(nees::kDof, b) - ChiSquareCdf(nees::kDof, a)));
  }
  ChartSpec c;
  c.title = "NEES distribution, " + Readable(w.length, 4) + " s windows";
  c.x.label = "NEES";
  c.x.log = true;
  c.y.label = "windows per bin";
  c.bars.push_back(std::move(bars));
  c.series.push_back(std::move(expected));
  c.lines.push_back({"chi2(9) bounds", r.chi2.lower, true, "#d62728"});
  c.lines.push_back({"", r.chi2.upper, true, "#d62728"});
  return ChartSvg(c);
}

// One error component against time with its ±3 sigma band; the caption counts those outside.
HtmlDocument::Figure ErrorComponent(const nees::WindowLengthResult& w, int block, int axis) {
  const std::size_t component = static_cast<std::size_t>(3 * block + axis);
  const int k = 3 * block + axis;
  ChartSpec c;
  c.width = 380.0;
  c.height = 210.0;
  c.title = std::string(kBlocks[block]) + "." + kAxes[axis];
  c.x.label = "window start [s]";
  c.y.label = std::string("error [") + kUnits[block] + "]";
  Band band{"\u00b13 sigma", {}, {}, {}, "#ff7f0e", 0.3};
  PointSeries err{"error", {}, {}, "#1f77b4", false, 1.6};
  std::size_t outside = 0;
  for (std::size_t i = 0; i < w.error.size(); ++i) {
    const double e = w.error[i](k), s = 3.0 * w.sigma[i](k);
    band.x.push_back(w.t_start[i]);
    band.lo.push_back(-s);
    band.hi.push_back(s);
    err.x.push_back(w.t_start[i]);
    err.y.push_back(e);
    outside += std::abs(e) > s ? 1 : 0;
  }
  c.bands.push_back(std::move(band));
  c.series.push_back(std::move(err));
  std::string fit;
  if (component < w.components.size()) {
    const nees::ComponentStatistics& s = w.components[component];
    fit = " Under k_gyro, k_accel: mean " + Readable(s.mean_standardized, 3) + ", rms " +
          Readable(s.rms_standardized, 3) + " sigma; " + std::to_string(s.positive) + " of " +
          std::to_string(s.nonzero) + " positive (sign test p " + Readable(s.sign_p_value, 2) +
          ")" + (s.offset ? ". OFFSET: the mean dominates the spread." : ".");
    // The flag on the figure itself, where the eye is.
    if (s.offset)
      c.title += "  \u2014 OFFSET (mean " + Readable(s.mean_standardized, 2) + " sigma)";
  }
  return {
      ChartSvg(c),
      std::string(kBlocks[block]) + "." + kAxes[axis] + ": " + std::to_string(outside) + " of " +
          std::to_string(w.error.size()) +
          " windows outside \u00b13 sigma of the declared densities (a Gaussian error: 0.27 %)." +
          fit};
}

// The offset-flagged components of one window length, in words.
std::string OffsetList(const nees::WindowLengthResult& w) {
  if (w.components.empty()) return "not judged (a sensor's densities are zero)";
  std::string s;
  for (const auto& c : w.components)
    if (c.offset)
      s += (s.empty() ? "" : ", ") + c.name + " (mean " + Readable(c.mean_standardized, 2) + ")";
  return s.empty() ? "none" : s;
}

}  // namespace

HtmlDocument NeesPage(const nees::Result& r, const Inputs& inputs) {
  HtmlDocument doc("imuconv nees");
  doc.AddParagraph(r.method + " in the " + r.convention + " chart; error [p, theta, v] (" +
                   std::to_string(nees::kDof) + " dof). chi-square(9): median " +
                   Readable(r.chi2.median, 5) + ", " + Readable(100 * nees::kConfidence, 3) +
                   " % bounds [" + Readable(r.chi2.lower, 5) + ", " + Readable(r.chi2.upper, 5) +
                   "]. Data span " + Readable(r.t_begin, 6) + " .. " + Readable(r.t_end, 6) +
                   " s.");
  std::vector<std::vector<std::string>> input_rows;
  for (const auto& [role, path] : inputs) input_rows.push_back({role, path});
  doc.AddTable({"input", "file"}, input_rows);
  doc.AddTable({"noise density", "value"},
               {{"gyro_noise_density", Readable(r.noise.gyro_noise_density, 6)},
                {"accel_noise_density", Readable(r.noise.accel_noise_density, 6)},
                {"gyro_random_walk", Readable(r.noise.gyro_random_walk, 6)},
                {"accel_random_walk", Readable(r.noise.accel_random_walk, 6)}});

  doc.AddHeading(2, "Summary");
  std::vector<std::vector<std::string>> rows;
  for (const auto& w : r.windows)
    rows.push_back({Readable(w.length, 4), Readable(w.stride, 4), std::to_string(w.nees.size()),
                    Readable(w.median, 4), Readable(w.mean, 4), Readable(w.p95, 4),
                    Readable(100 * w.fraction_inside, 3) + " %", Readable(w.factor, 4),
                    Readable(w.factor_gyro, 4), Readable(w.factor_accel, 4), OffsetList(w)});
  doc.AddTable({"window [s]", "stride [s]", "count", "median", "mean", "p95", "inside bounds",
                "k (all)", "k_gyro", "k_accel", "offsets"},
               rows);
  doc.AddParagraph(
      "k (all): the one scale on all four noise densities that puts the median NEES on the "
      "chi-square(9) median "
      "(NEES scales as 1/k^2); k > 1: the densities are too small for the data. k_gyro: the scale "
      "on the gyro "
      "densities alone that puts theta's median NEES (3 dof) on chi-square(3)'s median (theta's "
      "covariance "
      "depends on the gyro only); k_accel: then the scale on the accelerometer densities for the v "
      "block. "
      "Offsets: components whose standardized mean dominates the spread under the two factors (" +
      std::string(nees::kOffsetRule) + "): " + nees::kOffsetCauses);

  for (const auto& w : r.windows) {
    doc.AddHeading(2, Readable(w.length, 4) + " s windows");
    doc.AddParagraph("Factors: k (all) " + Readable(w.factor, 4) + ", k_gyro " +
                     Readable(w.factor_gyro, 4) + ", k_accel " + Readable(w.factor_accel, 4) +
                     ". Offsets: " + OffsetList(w) + ".");
    doc.AddFigures(
        {{NeesOverTime(r, w),
          "Each window's NEES at its start time; the dashed lines are chi-square(9)'s "
          "bounds, the solid one its median."},
         {NeesHistogram(r, w), "The windows' NEES in " + std::to_string(kHistogramBins) +
                                   " log-spaced bins against the counts chi-square(9) predicts."}});
    if (w.error.size() != w.nees.size()) {
      doc.AddParagraph("The errors were not kept for this result: no error time series.");
      continue;
    }
    doc.AddHeading(3, "End error of each window and its \u00b13 sigma");
    if (!w.components.empty()) {
      std::vector<std::vector<std::string>> comp_rows;
      for (const auto& s : w.components)
        comp_rows.push_back({s.name, Readable(s.mean_standardized, 3),
                             Readable(s.rms_standardized, 3),
                             std::to_string(s.positive) + " of " + std::to_string(s.nonzero),
                             Readable(s.sign_p_value, 2), s.offset ? "OFFSET" : ""});
      doc.AddTable({"component", "mean (sigma)", "rms (sigma)", "positive", "sign test p", "flag"},
                   comp_rows);
    }
    std::vector<HtmlDocument::Figure> figures;
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) figures.push_back(ErrorComponent(w, b, a));
    doc.AddFigures(figures);
  }
  return doc;
}

}  // namespace imuconv::report
