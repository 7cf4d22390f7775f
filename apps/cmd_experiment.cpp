// imuconv experiment preint-by-prop|prop-by-preint|both [--trials N] --seed S [--json] [--report
// OUT.html]: the note's two experiments (section 5, Figures 1 and 2) over random trials of 10 s at
// 200 Hz, their mean entrywise differences (docs/experiment.md; the logic is apps/experiment/).
// Exit code: 0 done, 2 unusable arguments or a failed trial (the message says which).
#include "imuconv/cli/cmd_experiment.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <thread>

#include "experiment_report.h"
#include "experiments.h"
#include "imuconv/cli/exit_codes.h"
#include "imuconv/printable.h"
#include "judgment.h"
#include "report_destination.h"
#include "summary.h"

namespace imuconv::cli {
namespace {

// The project's plausible IMU rates (README: 1 Hz to 100 kHz), and enough knots to integrate
// but not more than a trial should hold in memory. Throws Error naming the option.
void CheckTrialShape(const ExperimentCommandOptions& o) {
  if (!(std::isfinite(o.rate) && o.rate >= 1.0 && o.rate <= 1e5))
    throw Error("--rate " + std::to_string(o.rate) +
                ": expected a sample rate from 1 Hz to 100 kHz");
  if (!(std::isfinite(o.duration) && o.duration > 0.0))
    throw Error("--duration " + std::to_string(o.duration) +
                ": expected a positive number of seconds");
  const double steps = std::round(o.rate * o.duration) * o.propagator_substeps;
  if (steps < 2.0)
    throw Error("--duration " + std::to_string(o.duration) + " at --rate " +
                std::to_string(o.rate) + " Hz gives fewer than two steps; nothing to compare");
  if (steps > 1e6)
    throw Error("--rate x --duration x --propagator-substeps gives " + std::to_string(steps) +
                " steps per trial; at most 10^6");
}

// The methods the experiments need are loaded: the propagator asked for, and GTSAM's two
// schemes. Throws Error naming what is missing.
void CheckMethodsLoaded(const Registry& reg, const std::string& propagator) {
  if (!reg.has(PluginKind::Propagator, propagator)) {
    std::string known;
    for (const auto& id : reg.ids(PluginKind::Propagator)) known += " " + id;
    throw Error("--propagator: unknown propagator " + Printable(propagator) + "; known:" + known);
  }
  for (const char* id : {"manifold", "tangent"})
    if (!reg.has(PluginKind::Preintegrator, id))
      throw Error(
          std::string("the preintegrator '") + id +
          "' (GTSAM's scheme the experiments compare with) is not loaded; is the plugin directory "
          "complete?");
}

}  // namespace

int RunExperimentCommand(const CommandContext& ctx, const ExperimentCommandOptions& o) {
  std::optional<ReportDestination> report;
  const int exit_code = Judge(o.as_json, [&] {
    // The report's destination is examined before any work (a directory fails now, not after
    // the trials).
    report.emplace(o.report_path);
    CheckTrialShape(o);
    Registry reg;
    PrintLoadIssues(LoadRegistry(reg, ctx));
    CheckMethodsLoaded(reg, o.propagator);
    experiment::Options options;
    options.preint_by_prop = o.which != "prop-by-preint";
    options.prop_by_preint = o.which != "preint-by-prop";
    options.trials = o.trials;
    options.seed = o.seed;
    options.threads = o.threads > 0
                          ? o.threads
                          : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    options.threads = std::min(options.threads, experiment::kMaxThreads);
    options.spec.rate_hz = o.rate;
    options.spec.duration_s = o.duration;
    options.propagator = o.propagator;
    options.input = o.input == "zoh" ? experiment::PreintegratorInput::zoh
                                     : experiment::PreintegratorInput::mid;
    options.propagator_substeps = o.propagator_substeps;
    const auto result =
        std::make_shared<const experiment::Result>(experiment::RunExperiments(reg, options));
    // "wrote" comes after the summary (below), the last line a person reads.
    report->Write([&] { return experiment::ExperimentPage(*result); }, ctx, /*announce=*/false);
    Judgment judgment;
    judgment.SetResult(result, experiment::ResultJson, experiment::PrintSummary);
    judgment.exit_code = kExitOk;  // no verdict: the differences are the answer
    return judgment;
  });
  if (report) report->Announce(ctx);
  return exit_code;
}

// The command line of imuconv experiment: its description, and its flags onto the options.
static void DeclareExperimentCommand(CLI::App* sub, ExperimentCommandOptions* o) {
  sub->description(
      "Reproduce the note's experiments: preintegration by propagation "
      "and propagation by preintegration "
      "against GTSAM's two preintegration schemes, over random trials");
  sub->add_option("experiment", o->which,
                  "preint-by-prop (the note's Figure 1), prop-by-preint (Figure 2) or both")
      ->required()
      ->check(CLI::IsMember({"preint-by-prop", "prop-by-preint", "both"}));
  sub->add_option("--trials", o->trials, "Number of random trials (default 100, the note's)")
      ->check(CLI::Range(1, experiment::kMaxTrials));
  // NonNegativeNumber: CLI11 would otherwise read "-1" as 2^64 - 1.
  sub->add_option(
         "--seed", o->seed,
         "Seed; trial i is drawn from (seed, i), so the result does not depend on --threads")
      ->required()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--threads", o->threads, "Worker threads (default: every core)")
      ->check(CLI::Range(1, experiment::kMaxThreads));
  sub->add_option("--rate", o->rate, "Sample rate of the trials in Hz (default 200, the note's)")
      ->type_name("HZ");
  sub->add_option("--duration", o->duration,
                  "Length of each trial in seconds (default 10, the note's)")
      ->type_name("SECONDS");
  sub->add_option("--propagator", o->propagator,
                  "The propagation side (default rk4, the note's); a propagator of GTSAM's "
                  "manifold scheme on the "
                  "mid input, openvins_discrete, leaves only rounding in the manifold rows");
  sub->add_option("--input", o->input,
                  "What the preintegrators are fed: mid (GTSAM's mid-sample input, default) or zoh")
      ->check(CLI::IsMember({"mid", "zoh"}));
  sub->add_option("--propagator-substeps", o->propagator_substeps,
                  "Feed the propagator the samples with N-1 linearly interpolated knots per step "
                  "(for rk4: the same "
                  "input, a step N times smaller)")
      ->check(CLI::Range(1, 64));
  sub->add_flag(
      "--json", o->as_json,
      "Print one JSON object (schemas/experiment_output.schema.json) instead of the summary");
  AddReportOption(*sub, o->report_path,
                  "the note's Figures 1 and 2 as heatmaps of the mean entrywise difference");
}

void RegisterExperimentCommand(CLI::App& app, CommandContext& ctx) {
  AddCommand(app, ctx, "experiment", DeclareExperimentCommand, RunExperimentCommand);
}

}  // namespace imuconv::cli
