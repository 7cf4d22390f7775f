#include "imuconv/optimize/optimize_page.h"

#include <cmath>

#include "imuconv/report/chart.h"
#include "imuconv/report/markup.h"

namespace imuconv::optimize {

namespace {

using report::Band;
using report::ChartSpec;
using report::HtmlDocument;
using report::PointSeries;
using report::Readable;

constexpr const char* kAxes[3] = {"x", "y", "z"};

int Offset(const Result& r, const std::string& label) {
  for (std::size_t b = 0; b < r.labels.size(); ++b)
    if (r.labels[b] == label) return static_cast<int>(3 * b);
  return 0;
}

// One bias component over time: the estimate, its ±3 sigma band about it, and the reference.
HtmlDocument::Figure BiasComponent(const Result& r, bool gyro, int axis) {
  const std::string block = gyro ? "bg" : "ba";
  const int k = Offset(r, block) + axis;
  ChartSpec c;
  c.width = 380.0;
  c.height = 210.0;
  c.title = block + "." + kAxes[axis];
  c.x.label = "t [s]";
  c.y.label = gyro ? "rad/s" : "m/s\u00b2";
  Band band{"estimate \u00b13 sigma", {}, {}, {}, "#ff7f0e", 0.3};
  PointSeries est{"estimate", {}, {}, "#1f77b4", true, 1.6};
  PointSeries ref{"ground truth", {}, {}, "#2ca02c", true, 1.6};
  std::size_t inside = 0;
  for (const Keyframe& kf : r.keyframes) {
    const double b = gyro ? kf.x.bg[axis] : kf.x.ba[axis];
    est.x.push_back(kf.t);
    est.y.push_back(b);
    if (r.covariance_ok) {
      const double s = 3.0 * std::sqrt(kf.cov(k, k));
      band.x.push_back(kf.t);
      band.lo.push_back(b - s);
      band.hi.push_back(b + s);
      if (kf.has_reference_bias) {
        const double g = gyro ? kf.ref_bg[axis] : kf.ref_ba[axis];
        inside += std::abs(b - g) <= s ? 1 : 0;
      }
    }
    if (kf.has_reference_bias) {
      ref.x.push_back(kf.t);
      ref.y.push_back(gyro ? kf.ref_bg[axis] : kf.ref_ba[axis]);
    }
  }
  if (r.covariance_ok) c.bands.push_back(std::move(band));
  c.series.push_back(std::move(est));
  std::string caption = block + "." + kAxes[axis] + ": the estimate";
  if (!r.covariance_ok) caption += " (no covariance: " + r.covariance_message + ")";
  if (!ref.x.empty()) {
    c.series.push_back(std::move(ref));
    if (r.covariance_ok)
      caption += "; the ground truth's bias is within \u00b13 sigma at " + std::to_string(inside) +
                 " of " + std::to_string(r.keyframes.size()) + " keyframes";
  }
  return {report::ChartSvg(c), caption + "."};
}

}  // namespace

HtmlDocument OptimizePage(const Result& r, const PageInputs& inputs) {
  HtmlDocument doc("imuconv optimize");
  doc.AddParagraph(std::to_string(r.keyframes.size()) + " keyframes every " +
                   Readable(r.keyframe_step, 6) + " s; preintegration factors of " + r.method +
                   " (" + r.kind + " residual), the solver stepping in the " + r.convention +
                   " chart, covariances in it.");
  // Not AddVerdict: convergence is no consistency judgment, but it is said first all the same.
  doc.AddParagraph(r.converged ? "The solve converged (" + r.solver_message + ")."
                               : "THE SOLVE DID NOT CONVERGE: " + r.solver_message +
                                     ". The estimates below are where it stopped, not an optimum.");
  std::vector<std::vector<std::string>> input_rows;
  for (const auto& [role, path] : inputs) input_rows.push_back({role, path});
  doc.AddTable({"input", "file"}, input_rows);
  doc.AddHeading(2, "Solver");
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < r.rounds.size(); ++i) {
    const Round& rd = r.rounds[i];
    rows.push_back({std::to_string(i + 1), std::to_string(rd.iterations),
                    Readable(rd.initial_cost, 6), Readable(rd.final_cost, 6), rd.termination,
                    Readable(rd.seconds, 3), std::to_string(rd.reintegrated)});
  }
  doc.AddTable({"solve", "iterations", "initial cost", "final cost", "termination", "time [s]",
                "factors re-integrated after it"},
               rows);
  if (r.pending_reintegration > 0)
    doc.AddParagraph(std::to_string(r.pending_reintegration) +
                     " factors' start biases still moved beyond the re-integration thresholds "
                     "after the last solve; they are first-order corrected.");
  doc.AddHeading(2, "Biases over time");
  if (r.has_reference_bias && r.covariance_ok)
    doc.AddTable(
        {"", "x", "y", "z"},
        {{"bg RMS vs ground truth [rad/s]", Readable(r.bias.rms_bg.x(), 3),
          Readable(r.bias.rms_bg.y(), 3), Readable(r.bias.rms_bg.z(), 3)},
         {"ba RMS vs ground truth [m/s\u00b2]", Readable(r.bias.rms_ba.x(), 3),
          Readable(r.bias.rms_ba.y(), 3), Readable(r.bias.rms_ba.z(), 3)},
         {"bg within 3 sigma", Readable(r.bias.within_3sigma_bg.x(), 3),
          Readable(r.bias.within_3sigma_bg.y(), 3), Readable(r.bias.within_3sigma_bg.z(), 3)},
         {"ba within 3 sigma", Readable(r.bias.within_3sigma_ba.x(), 3),
          Readable(r.bias.within_3sigma_ba.y(), 3), Readable(r.bias.within_3sigma_ba.z(), 3)}});
  else if (!r.has_reference_bias)
    doc.AddParagraph("The poses file has no biases (poses only): the estimates are drawn alone.");
  for (const bool gyro : {true, false}) {
    std::vector<HtmlDocument::Figure> figures;
    for (int a = 0; a < 3; ++a) figures.push_back(BiasComponent(r, gyro, a));
    doc.AddFigures(figures);
  }
  return doc;
}

}  // namespace imuconv::optimize
