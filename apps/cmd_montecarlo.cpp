// imuconv montecarlo (--case CASE.json | --pipeline P.json [--from T] [--to T]) --method M
//                    [--convention C] --trials N --seed S [--json]:
// N noisy re-integrations of a reference case's samples with one propagator (preintegration by
// propagation) or preintegrator, their end errors against the covariance it predicts
// (docs/montecarlo.md; the logic is apps/montecarlo/).
// Across machines: `... --shard K/N -o FILE` runs its block of the trials and writes their end
// errors to a shard file (apps/montecarlo/shard.h); `imuconv montecarlo --merge FILE...` checks
// the N files are one whole run and prints, and exits with, what that run would have.
// Exit code: 0 consistent (or a shard written), 1 inconsistent, 2 unusable input (the message
// names the file, the JSON pointer or the option).
#include "imuconv/cli/cmd_montecarlo.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <thread>
#include <utility>

#include "imuconv/bridge.h"
#include "imuconv/cli/exit_codes.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/pipeline/output_file.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/pipeline_data.h"
#include "imuconv/printable.h"
#include "judgment.h"
#include "montecarlo.h"
#include "montecarlo_report.h"
#include "refcase.h"
#include "report/pages/pages.h"
#include "report_destination.h"
#include "shard.h"

namespace imuconv::cli {
namespace {

std::string KnownMethods(const Registry& reg) {
  std::string s = "propagators: ";
  for (const auto& id : reg.ids(PluginKind::Propagator)) s += id + " ";
  s += "; preintegrators: ";
  for (const auto& id : reg.ids(PluginKind::Preintegrator)) s += id + " ";
  return s;
}

// Which of the three forms the options make: a merge (true), else a run, or with `shard` set
// its shard {K, N}. Throws Error for a mix or a form's missing option.
bool CheckForm(const MontecarloCommandOptions& o, std::optional<std::pair<int, int>>& shard) {
  const bool merging = !o.merge_files.empty();
  if (merging) {
    // The options of a run or a shard, none of which a merge takes (its run is the shards').
    const std::pair<const char*, bool> run_only[] = {{"--case", o.case_path.has_value()},
                                                     {"--pipeline", o.pipeline_path.has_value()},
                                                     {"--from", o.from.has_value()},
                                                     {"--to", o.to.has_value()},
                                                     {"--method", o.method.has_value()},
                                                     {"--trials", o.trials.has_value()},
                                                     {"--seed", o.seed.has_value()},
                                                     {"--shard", o.shard.has_value()},
                                                     {"--output", o.shard_output.has_value()},
                                                     {"--convention", o.convention.has_value()},
                                                     {"--threads", o.threads.has_value()},
                                                     {"--duration", o.duration.has_value()},
                                                     {"--noise-scale", o.noise_scale.has_value()}};
    for (const auto& [name, given] : run_only)
      if (given)
        throw Error(std::string("--merge takes the run from its shards; ") + name +
                    " is not used with it");
  } else {
    std::string missing;
    if (!o.case_path && !o.pipeline_path) missing = "--case (or --pipeline)";
    for (const auto& [name, given] :
         {std::pair<const char*, bool>{"--method", o.method.has_value()},
          {"--trials", o.trials.has_value()},
          {"--seed", o.seed.has_value()}})
      if (!given) missing += (missing.empty() ? "" : ", ") + std::string(name);
    if (!missing.empty()) throw Error(missing + ": required (or --merge SHARD...)");
    if (o.case_path && o.pipeline_path)
      throw Error("give the samples with one of --case CASE.json or --pipeline P.json, not both");
  }
  if (o.shard) {
    try {
      const auto [index, count] = ParseShardOption(*o.shard);
      shard = {static_cast<int>(index), static_cast<int>(count)};
    } catch (const UsageError& u) {
      throw Error(u.message);
    }
    if (o.shard_output.value_or("").empty())
      throw Error("--shard K/N needs -o FILE: the shard file imuconv montecarlo --merge reads");
    if (!o.pipeline_path.value_or("").empty())
      throw Error(
          "--shard takes --case: a shard records its case file's digest, and a pipeline's samples "
          "are in "
          "other files");
    if (o.as_json || !o.report_path.empty())
      throw Error(
          "--shard writes its trials' end errors, not statistics: --json and --report go with "
          "--merge");
  } else if (o.shard_output) {
    throw Error(
        "-o is the shard file of --shard K/N; a whole run prints its summary or --json to stdout");
  }
  return merging;
}

// The run's samples over --from/--to and --duration, and its noise and bias estimate: the
// case's (what it leaves out takes its standard value, said in a note), or the pipeline's with
// a zero bias estimate.
montecarlo::Input ReadRunInput(const CommandContext& ctx, const MontecarloCommandOptions& o) {
  const std::string case_path = o.case_path.value_or(""),
                    pipeline_path = o.pipeline_path.value_or("");
  montecarlo::Input input;
  std::vector<ImuSample> samples;
  if (pipeline_path.empty()) {
    const nlohmann::json case_json = pipeline::ParseJsonFile(case_path);
    refcase::Case c;
    std::vector<std::string> defaulted;
    try {
      c = refcase::ParseCase(case_json, refcase::CaseKeys::samples_and_noise, &defaulted);
    } catch (const std::exception& e) {
      throw Error(Printable(case_path) + ": " + e.what());
    }
    if (!defaulted.empty() && !ctx.quiet()) {
      std::string list;
      for (const std::string& d : defaulted) list += (list.empty() ? "" : ", ") + d;
      std::cerr << "imuconv: note: " << Printable(case_path)
                << ": not given, standard values used: " << list
                << " (docs/montecarlo.md, \"Input\")\n";
    }
    input.noise = c.noise;
    input.bg = c.x_s.bg;
    input.ba = c.x_s.ba;
    samples = std::move(c.samples);
  } else {
    const pipeline::Pipeline p = pipeline::Pipeline::Load(pipeline_path);
    input.noise = pipeline::PipelineNoise(p, "imuconv montecarlo simulates and predicts with it");
    samples = pipeline::ReadPipelineImu(p).samples;  // its timing checked as imuconv run checks it
  }
  // The interval: --from/--to, then --duration from its start.
  const double t_from = o.from ? *o.from : samples.front().t;
  double t_to = o.to ? *o.to : samples.back().t;
  if (!std::isfinite(t_from) || !std::isfinite(t_to) || !(t_from < t_to))
    throw Error("--from " + std::to_string(t_from) + " --to " + std::to_string(t_to) +
                ": expected finite times with --from before --to");
  // A time outside the samples is refused, as imuconv run refuses one: cut to the data in
  // silence, --to 100 on 20 s of samples would simulate another interval than the one asked
  // for. 1e-6 s: the measurements form's agreement of two statements of one time.
  const auto refuse_outside = [&](const char* option, const std::optional<double>& t) {
    if (!t || (*t >= samples.front().t - 1e-6 && *t <= samples.back().t + 1e-6)) return;
    char given[32];
    std::snprintf(given, sizeof given, "%.9g", *t);
    throw Error(std::string(option) + " " + given + ": outside the samples of " +
                Printable(pipeline_path.empty() ? case_path : pipeline_path) +
                " (the samples span [" + std::to_string(samples.front().t) + ", " +
                std::to_string(samples.back().t) + "] s)");
  };
  refuse_outside("--from", o.from);
  refuse_outside("--to", o.to);
  const double duration = o.duration.value_or(0.0);
  for (const ImuSample& smp : samples)
    if (smp.t >= t_from - 1e-9) {
      if (duration > 0) t_to = std::min(t_to, smp.t + duration);
      break;
    }
  for (const ImuSample& smp : samples)
    if (smp.t >= t_from - 1e-9 && smp.t <= t_to + 1e-9) input.samples.push_back(smp);
  if (input.samples.size() < 2)
    throw Error(Printable(pipeline_path.empty() ? case_path : pipeline_path) + ": the interval [" +
                std::to_string(t_from) + ", " + std::to_string(t_to) + "] s holds " +
                std::to_string(input.samples.size()) + " samples (the samples span [" +
                std::to_string(samples.front().t) + ", " + std::to_string(samples.back().t) +
                "] s); need at least two to integrate");
  return input;
}

// A progress bar on stderr for a person watching: only when stderr is a terminal, never with
// --json (a program reads that) nor with -q; the line is cleared when the trials are done.
class ProgressBar {
 public:
  ProgressBar(const CommandContext& ctx, bool as_json, montecarlo::Options& options)
      : on_(!as_json && !ctx.quiet() && isatty(STDERR_FILENO) == 1) {
    if (on_)
      options.progress = [](int done, int total) {
        const int width = 40,
                  filled = static_cast<int>(static_cast<long long>(width) * done / total);
        std::cerr << "\rmontecarlo [" << std::string(filled, '#')
                  << std::string(width - filled, '.') << "] " << done << "/" << total << std::flush;
      };
  }
  ~ProgressBar() {
    if (on_) std::cerr << "\r\033[K" << std::flush;
  }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

 private:
  bool on_;
};

Judgment Concluded(const std::shared_ptr<const montecarlo::Result>& result) {
  Judgment judgment;
  judgment.SetResult(result, montecarlo::ReportJson, montecarlo::PrintSummary);
  judgment.exit_code =
      result->verdict == montecarlo::Verdict::consistent ? kExitOk : kExitInconsistent;
  return judgment;
}

}  // namespace

int RunMontecarloCommand(const CommandContext& ctx, const MontecarloCommandOptions& o) {
  return Judge(o.as_json, [&] {
    std::optional<std::pair<int, int>> shard;
    const bool merging = CheckForm(o, shard);
    const std::string case_path = o.case_path.value_or(""),
                      pipeline_path = o.pipeline_path.value_or("");
    // The report's destination is examined before any work (a directory or an input fails now).
    ReportDestination report(o.report_path);
    if (merging)
      for (const std::string& f : o.merge_files) report.RefuseIfSame(f, "a shard");
    else
      report.RefuseIfSame(pipeline_path.empty() ? case_path : pipeline_path,
                          pipeline_path.empty() ? "the case file" : "the pipeline file");
    if (merging) {
      std::string merged_case;  // the shards' case file, as the first shard names it
      std::shared_ptr<const montecarlo::Result> result;
      try {
        result = std::make_shared<const montecarlo::Result>(
            montecarlo::MergeShards(o.merge_files, merged_case));
      } catch (const std::exception& e) {
        throw Error(std::string("--merge: ") + e.what());
      }
      report.Write([&] { return report::MontecarloPage(*result, {{"case", merged_case}}); }, ctx);
      return Concluded(result);
    }
    // The shard file's destination too is examined before any work.
    std::optional<pipeline::OutputFile> shard_out;
    if (shard) {
      shard_out.emplace(*o.shard_output);
      shard_out->refuse_if_same(case_path, "the case file");
    }
    const int trials = *o.trials;
    if (trials > montecarlo::kMaxTrials)
      throw Error("--trials " + std::to_string(trials) + ": at most " +
                  std::to_string(montecarlo::kMaxTrials) +
                  " (each trial's 15-dim error is kept for the statistics)");
    if (trials < montecarlo::kDim + 1)
      throw Error("--trials " + std::to_string(trials) +
                  ": need at least 16 (the sample covariance of 15-dim errors is singular below, "
                  "its KL divergence "
                  "infinite)");
    Registry reg;
    const std::vector<LoadIssue> issues = LoadRegistry(reg, ctx);
    PrintLoadIssues(issues);

    const std::string& method_id = *o.method;
    PreintegrationMethod method;
    if (reg.has(PluginKind::Propagator, method_id))
      method = ResolvePreintegrationMethod(reg, PluginKind::Propagator, method_id);
    else if (reg.has(PluginKind::Preintegrator, method_id))
      method = ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, method_id);
    else
      throw Error("--method: unknown method " + Printable(method_id) + "; known " +
                  KnownMethods(reg));
    const std::string conv =
        o.convention.value_or("").empty() ? montecarlo::DefaultConvention(method) : *o.convention;
    const std::string unknown =
        UnknownConventionMessage(reg, PluginKind::IncrementConvention, conv, issues);
    if (!unknown.empty()) throw Error("--convention: " + unknown);

    const montecarlo::Input input = ReadRunInput(ctx, o);
    montecarlo::Options options;
    options.trials = trials;
    options.seed = *o.seed;
    const int threads = o.threads.value_or(0);
    options.threads =
        threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    options.noise_scale = o.noise_scale.value_or(1.0);
    const ProgressBar progress(ctx, o.as_json, options);
    if (shard) {
      // Its block of trials, seeded from (seed, i) as in the whole run, and what identifies the
      // run.
      const auto [first, end] = montecarlo::ShardTrials(trials, shard->first, shard->second);
      std::vector<Vec15> errors;
      const montecarlo::Result head =
          montecarlo::RunTrials(reg, method, conv, input, options, first, end, errors);
      const nlohmann::json provenance =
          montecarlo::ShardProvenance(reg, method, head.convention, case_path);
      shard_out->refuse_if_loaded_object();
      montecarlo::WriteShard([&](std::string_view piece) { shard_out->write(piece); }, shard->first,
                             shard->second, first, end, montecarlo::ShardRunJson(head, provenance),
                             errors);
      std::cout.flush();
      shard_out->commit();
      if (!ctx.quiet() && !shard_out->is_stdout())
        std::cout << "wrote " << Printable(*o.shard_output) << " (shard " << shard->first << "/"
                  << shard->second << ": trials [" << first << ", " << end << ") of " << trials
                  << ")\n";
      Judgment written;
      written.printed_elsewhere =
          true;  // the shard file is the output; its statistics come with --merge
      return written;
    }
    const auto result = std::make_shared<const montecarlo::Result>(
        montecarlo::RunMonteCarlo(reg, method, conv, input, options));
    report.Write(
        [&] {
          return report::MontecarloPage(
              *result,
              {pipeline_path.empty() ? report::Inputs::value_type{"case", case_path}
                                     : report::Inputs::value_type{"pipeline", pipeline_path}});
        },
        ctx);
    return Concluded(result);
  });
}

// The command line of imuconv montecarlo: its description, and its flags onto the options.
static void DeclareMontecarloCommand(CLI::App* sub, MontecarloCommandOptions* o) {
  sub->description(
      "Re-integrate a case's samples N times with noise and compare the "
      "errors with the predicted covariance");
  // --case, --method, --trials and --seed are required but for --merge (checked by the run).
  sub->add_option(
      "--case", o->case_path,
      "Reference case with the IMU samples, noise and bias estimate "
      "(tests/data/reference/FORMAT.md); only "
      "/imu and /noise are required, the rest takes its standard value (docs/montecarlo.md)");
  sub->add_option("--pipeline", o->pipeline_path,
                  "Instead of --case: a pipeline's IMU samples and noise (its /imu, /noise), over "
                  "--from/--to; zero bias estimate");
  sub->add_option(
         "--from", o->from,
         "Integrate from this time (seconds on the samples' time axis; default: the first)")
      ->type_name("T");
  sub->add_option(
         "--to", o->to,
         "Integrate up to this time (seconds on the samples' time axis; default: the last)")
      ->type_name("T");
  sub->add_option("--method", o->method,
                  "A propagator (preintegration by propagation) or a preintegrator id");
  sub->add_option(
      "--convention", o->convention,
      "Increment convention the end error is scored in (default: the preintegrator's covariance "
      "convention, or preint_reference for a propagator)");
  sub->add_option("--trials", o->trials,
                  "Number of noisy trials N (at least 16: 15-dim errors need 16 for a full-rank "
                  "sample covariance)");
  // NonNegativeNumber: CLI11 would otherwise read "-1" as 2^64 - 1, a wrong seed given in silence.
  sub->add_option("--seed", o->seed,
                  "Seed; trial i draws from (seed, i), so the result does not depend on --threads")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--threads", o->threads, "Worker threads (default: every core)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--duration", o->duration,
                  "Use only the case's first SECONDS (default: all of it)")
      ->type_name("SECONDS")
      ->check(CLI::PositiveNumber);
  // Hidden: scales the simulated densities only, against the unscaled prediction, to show that
  // a wrong noise model is detected (tests/cli/montecarlo.cpp).
  sub->add_option("--noise-scale", o->noise_scale, "")->group("")->check(CLI::PositiveNumber);
  sub->add_flag(
      "--json", o->as_json,
      "Print one JSON object (schemas/montecarlo_output.schema.json) instead of the summary");
  AddReportOption(
      *sub, o->report_path,
      "heatmaps of the sample covariance against the predicted one, and the summary (replaced "
      "atomically)");
  sub->add_option("--shard", o->shard,
                  "Run only shard K of N (0 <= K < N): the contiguous block of trials [K N_trials "
                  "/ N, (K+1) "
                  "N_trials / N), their end errors written to -o FILE; imuconv montecarlo --merge "
                  "joins the N "
                  "files into the whole run's output (docs/montecarlo.md)")
      ->type_name("K/N");
  AddOutputPathOption(*sub, "-o,--output", o->shard_output,
                      "With --shard: the shard file (replaced atomically)", "FILE");
  sub->add_option("--merge", o->merge_files,
                  "Join the N shard files of one run (any order; every K once) and print, and exit "
                  "with, what the "
                  "whole run would have (--json, --report as for a run); the run's options come "
                  "from the shards")
      ->type_name("SHARD...");
}

void RegisterMontecarloCommand(CLI::App& app, CommandContext& ctx) {
  AddCommand(app, ctx, "montecarlo", DeclareMontecarloCommand, RunMontecarloCommand);
}

}  // namespace imuconv::cli
