// imuconv experiment preint-by-prop|prop-by-preint|both [--trials N] --seed S [--json] [--report OUT.html]: the note's
// two experiments (section 5, Figures 1 and 2) over random trials of 10 s at 200 Hz, their mean
// entrywise differences (docs/experiment.md; the logic is apps/experiment/).
// Exit code: 0 done, 2 unusable arguments or a failed trial (the message says which).
#include <cmath>
#include <iostream>
#include <optional>
#include <thread>

#include "commands.h"
#include "exit_codes.h"
#include "experiment_report.h"
#include "experiments.h"
#include "imuconv/report/report_output.h"
#include "imuconv/printable.h"
#include "summary.h"

namespace imuconv::cli {

void RegisterExperimentCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand(
      "experiment",
      "Reproduce the note's experiments: preintegration by propagation and propagation by preintegration "
      "against GTSAM's two preintegration schemes, over random trials");
  static std::string which, propagator = "rk4", input = "mid";
  static int trials = 100, threads = 0, substeps = 1;
  static std::uint64_t seed = 0;
  static double rate = 200.0, duration = 10.0;
  static bool as_json = false;
  static std::string report_path;
  sub->add_option("experiment", which,
                  "preint-by-prop (the note's Figure 1), prop-by-preint (Figure 2) or both")
      ->required()
      ->check(CLI::IsMember({"preint-by-prop", "prop-by-preint", "both"}));
  sub->add_option("--trials", trials, "Number of random trials (default 100, the note's)")
      ->check(CLI::Range(1, experiment::kMaxTrials));
  // NonNegativeNumber: CLI11 would otherwise read "-1" as 2^64 - 1.
  sub->add_option("--seed", seed, "Seed; trial i is drawn from (seed, i), so the result does not depend on --threads")
      ->required()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--threads", threads, "Worker threads (default: every core)")
      ->check(CLI::Range(1, experiment::kMaxThreads));
  sub->add_option("--rate", rate, "Sample rate of the trials in Hz (default 200, the note's)")->type_name("HZ");
  sub->add_option("--duration", duration, "Length of each trial in seconds (default 10, the note's)")
      ->type_name("SECONDS");
  sub->add_option("--propagator", propagator,
                  "The propagation side (default rk4, the note's); a propagator of GTSAM's manifold scheme on the "
                  "mid input, openvins_discrete, leaves only rounding in the manifold rows");
  sub->add_option("--input", input, "What the preintegrators are fed: mid (GTSAM's mid-sample input, default) or zoh")
      ->check(CLI::IsMember({"mid", "zoh"}));
  sub->add_option("--propagator-substeps", substeps,
                  "Feed the propagator the samples with N-1 linearly interpolated knots per step (for rk4: the same "
                  "input, a step N times smaller)")
      ->check(CLI::Range(1, 64));
  sub->add_flag("--json", as_json,
                "Print one JSON object (schemas/experiment_output.schema.json) instead of the summary");
  sub->add_option("--report", report_path,
                  "Also write a self-contained HTML report: the note's Figures 1 and 2 as heatmaps of the mean "
                  "entrywise difference")
      ->type_name("OUT.html")
      ->check(OutputPathCheck());
  AddPluginDirOption(*sub, ctx);
  sub->callback([&ctx] {
    experiment::Result result;
    std::optional<report::ReportOutput> report_out;
    try {
      // The report's destination is examined before any work (a directory fails now, not after
      // the trials).
      if (!report_path.empty()) report_out.emplace(report_path);
      // The project's plausible IMU rates (README: 1 Hz to 100 kHz), and enough knots to
      // integrate but not more than a trial should hold in memory.
      if (!(std::isfinite(rate) && rate >= 1.0 && rate <= 1e5))
        throw Error("--rate " + std::to_string(rate) + ": expected a sample rate from 1 Hz to 100 kHz");
      if (!(std::isfinite(duration) && duration > 0.0))
        throw Error("--duration " + std::to_string(duration) + ": expected a positive number of seconds");
      const double steps = std::round(rate * duration) * substeps;
      if (steps < 2.0)
        throw Error("--duration " + std::to_string(duration) + " at --rate " + std::to_string(rate) +
                    " Hz gives fewer than two steps; nothing to compare");
      if (steps > 1e6)
        throw Error("--rate x --duration x --propagator-substeps gives " + std::to_string(steps) +
                    " steps per trial; at most 10^6");
      Registry reg;
      for (const auto& i : LoadRegistry(reg, ctx))
        std::cerr << "imuconv: warning: " << Printable(i.file) << ": " << Printable(i.message) << "\n";
      if (!reg.has(PluginKind::Propagator, propagator)) {
        std::string known;
        for (const auto& id : reg.ids(PluginKind::Propagator)) known += " " + id;
        throw Error("--propagator: unknown propagator " + Printable(propagator) + "; known:" + known);
      }
      for (const char* id : {"manifold", "tangent"})
        if (!reg.has(PluginKind::Preintegrator, id))
          throw Error(std::string("the preintegrator '") + id +
                      "' (GTSAM's scheme the experiments compare with) is not loaded; is the plugin directory "
                      "complete?");
      experiment::Options o;
      o.preint_by_prop = which != "prop-by-preint";
      o.prop_by_preint = which != "preint-by-prop";
      o.trials = trials;
      o.seed = seed;
      o.threads = threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
      o.threads = std::min(o.threads, experiment::kMaxThreads);
      o.spec.rate_hz = rate;
      o.spec.duration_s = duration;
      o.propagator = propagator;
      o.input = input == "zoh" ? experiment::PreintegratorInput::zoh : experiment::PreintegratorInput::mid;
      o.propagator_substeps = substeps;
      result = experiment::RunExperiments(reg, o);
      if (report_out) {
        report_out->RefuseIfLoadedObject();
        report_out->Write(experiment::ExperimentPage(result));
      }
    } catch (const std::exception& e) {
      ctx.exit_code = ReportFailure(e);
      return;
    }
    if (as_json)
      std::cout << experiment::ResultJson(result).dump(1) << "\n";
    else
      experiment::PrintSummary(std::cout, result);
    if (report_out && !ctx.quiet()) std::cerr << "wrote " << Printable(report_path) << "\n";
    ctx.exit_code = 0;
  });
}

}  // namespace imuconv::cli
