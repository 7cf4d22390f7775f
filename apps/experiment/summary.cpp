#include "summary.h"

#include <cstdio>
#include <string>

#include "imuconv/pipeline/json_io.h"

namespace imuconv::experiment {

std::string Sci(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2e", x);
  return buf;
}

namespace {

std::string Input(const Options& o) { return o.input == PreintegratorInput::mid ? "mid" : "zoh"; }

void PrintTable(std::ostream& out, const Result& r, const std::string& experiment) {
  char line[200];
  std::snprintf(line, sizeof line, "  %-6s %-9s %-24s %11s %11s  %11s %11s  %s\n", "matrix",
                "scheme", "chart", "note d mean", "max", "scaled mean", "max", "scaled d");
  out << line;
  for (const Comparison& c : r.comparisons) {
    if (c.experiment != experiment) continue;
    std::snprintf(
        line, sizeof line, "  %-6s %-9s %-24s %11s %11s  %11s %11s  %s\n", c.matrix.c_str(),
        c.preintegrator.c_str(), c.chart.c_str(), Sci(c.note_mean).c_str(), Sci(c.note_max).c_str(),
        Sci(c.scaled_mean).c_str(), Sci(c.scaled_max).c_str(),
        c.scaled_metric == "correlation" ? "correlation scale" : "relative, floor 1e-4 of max");
    out << line;
  }
}

}  // namespace

void PrintSummary(std::ostream& out, const Result& r) {
  const Options& o = r.options;
  out << "imuconv experiment: " << o.trials << " random trial" << (o.trials == 1 ? "" : "s")
      << " of " << o.spec.duration_s << " s at " << o.spec.rate_hz << " Hz (seed " << o.seed
      << "); propagator " << o.propagator << " on the samples"
      << (o.propagator_substeps > 1 ? " subdivided " + std::to_string(o.propagator_substeps) + "x"
                                    : "")
      << ", preintegrators manifold and tangent on GTSAM's " << Input(o) << " input\n";
  out << "d per entry, averaged over trials and entries (mean) or its largest over both (max):\n"
         "  note d:   the note's |r - e| / |r| where |r| > 1e-4, else |r - e| (r the reference)\n"
         "  scaled d: imuconv check's scale-aware d (a covariance on the correlation scale, other "
         "matrices\n"
         "            relative above 1e-4 of their largest entry), which also sees the tiny bias "
         "blocks\n";
  if (o.preint_by_prop) {
    out << "\npreintegration by propagation (note, section 3.1; Figure 1): " << o.propagator
        << " propagated from the identity and converted, against the preintegrator (the "
           "reference), in "
           "GTSAM's charts\n";
    PrintTable(out, r, "preint-by-prop");
  }
  if (o.prop_by_preint) {
    out << "\npropagation by preintegration (note, section 3.2; Figure 2): Phi and the covariance "
           "from the "
           "preintegrator's\nmeasurement, against "
        << o.propagator
        << " propagation (the reference) from the trial's random state and covariance, in left\n";
    PrintTable(out, r, "prop-by-preint");
  }
  out << "\nWhy not zero: the two sides discretise the same equations differently. "
      << (o.propagator == "rk4" ? "rk4 integrates the linearly\ninterpolated samples to 4th order; "
                                  "GTSAM's schemes hold the mid "
                                  "value over each step, freeze the\nrotation over a step for p "
                                  "and v, and take the noise as "
                                  "sigma^2/dt per step (first order).\nThe bridge itself is exact: "
                                  "with a propagator of GTSAM's "
                                  "manifold scheme (--propagator\nopenvins_discrete) the manifold "
                                  "rows fall to rounding "
                                  "(docs/experiment.md).\n"
                                : "With a propagator of the\npreintegrator's own scheme only "
                                  "rounding is left (docs/experiment.md).\n");
}

nlohmann::json ResultJson(const Result& r) {
  const Options& o = r.options;
  nlohmann::json j;
  j["command"] = "experiment";
  nlohmann::json exps = nlohmann::json::array();
  if (o.preint_by_prop) exps.push_back("preint-by-prop");
  if (o.prop_by_preint) exps.push_back("prop-by-preint");
  j["experiments"] = exps;
  j["trials"] = o.trials;
  j["seed"] = o.seed;
  j["rate_hz"] = o.spec.rate_hz;
  j["duration_s"] = o.spec.duration_s;
  j["propagator"] = o.propagator;
  j["propagator_substeps"] = o.propagator_substeps;
  j["preintegrators"] = {"manifold", "tangent"};
  j["preintegrator_input"] = Input(o);
  j["metrics"] = {{"note_d", "|r - e| / |r| where |r| > 1e-4, else |r - e|; r the reference entry"},
                  {"scaled_d",
                   "correlation: |r - e| / sqrt(r_ii r_jj); relative_above_floor: |r - e| / "
                   "max(|r|, 1e-4 max|R|)"}};
  nlohmann::json cmps = nlohmann::json::array();
  for (const Comparison& c : r.comparisons) {
    nlohmann::json x;
    x["experiment"] = c.experiment;
    x["preintegrator"] = c.preintegrator;
    x["matrix"] = c.matrix;
    x["reference"] = c.reference;
    x["chart"] = c.chart;
    x["row_blocks"] = c.row_blocks;
    x["col_blocks"] = c.col_blocks;
    x["note_d"] = {{"mean", c.note_mean},
                   {"max", c.note_max},
                   {"mean_matrix", pipeline::MatrixToJson(c.mean_note_d)}};
    x["scaled_d"] = {{"metric", c.scaled_metric},
                     {"mean", c.scaled_mean},
                     {"max", c.scaled_max},
                     {"worst_trial", c.worst_trial},
                     {"mean_matrix", pipeline::MatrixToJson(c.mean_scaled_d)}};
    cmps.push_back(x);
  }
  j["comparisons"] = cmps;
  return j;
}

}  // namespace imuconv::experiment
