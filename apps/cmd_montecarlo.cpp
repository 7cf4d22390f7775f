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
#include <unistd.h>

#include <cmath>
#include <iostream>
#include <optional>
#include <thread>

#include "commands.h"
#include "exit_codes.h"
#include "imuconv/bridge.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/pipeline/output_file.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/pipeline_data.h"
#include "imuconv/printable.h"
#include "imuconv/report/report_output.h"
#include "montecarlo.h"
#include "montecarlo_report.h"
#include "refcase.h"
#include "report/pages/pages.h"
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

}  // namespace

void RegisterMontecarloCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand(
      "montecarlo",
      "Re-integrate a case's samples N times with noise and compare the errors with the predicted covariance");
  static std::string case_path, pipeline_path, method_id, convention;
  static double from_t = 0.0, to_t = 0.0;
  static int trials = 0;
  static std::uint64_t seed = 0;
  static int threads = 0;
  static double duration = 0.0, noise_scale = 1.0;
  static bool as_json = false;
  // --case, --method, --trials and --seed are required but for --merge (checked in the callback).
  auto* case_opt = sub->add_option(
      "--case", case_path,
      "Reference case with the IMU samples, noise and bias estimate (tests/data/reference/FORMAT.md); only /imu and "
      "/noise are required, the rest takes its standard value (docs/montecarlo.md)");
  auto* pipeline_opt = sub->add_option(
      "--pipeline", pipeline_path,
      "Instead of --case: a pipeline's IMU samples and noise (its /imu, /noise), over --from/--to; zero bias estimate");
  auto* from_opt = sub->add_option("--from", from_t,
                                   "Integrate from this time (seconds on the samples' time axis; default: the first)")
                       ->type_name("T");
  auto* to_opt =
      sub->add_option("--to", to_t, "Integrate up to this time (seconds on the samples' time axis; default: the last)")
          ->type_name("T");
  auto* method_opt =
      sub->add_option("--method", method_id, "A propagator (preintegration by propagation) or a preintegrator id");
  auto* convention_opt = sub->add_option(
      "--convention", convention,
      "Increment convention the end error is scored in (default: the preintegrator's covariance convention, "
      "or preint_reference for a propagator)");
  auto* trials_opt =
      sub->add_option("--trials", trials,
                      "Number of noisy trials N (at least 16: 15-dim errors need 16 for a full-rank sample "
                      "covariance)");
  // NonNegativeNumber: CLI11 would otherwise read "-1" as 2^64 - 1, a wrong seed given in silence.
  auto* seed_opt =
      sub->add_option("--seed", seed, "Seed; trial i draws from (seed, i), so the result does not depend on --threads")
          ->check(CLI::NonNegativeNumber);
  auto* threads_opt =
      sub->add_option("--threads", threads, "Worker threads (default: every core)")->check(CLI::PositiveNumber);
  auto* duration_opt = sub->add_option("--duration", duration, "Use only the case's first SECONDS (default: all of it)")
                           ->type_name("SECONDS")
                           ->check(CLI::PositiveNumber);
  // Hidden: scales the simulated densities only, against the unscaled prediction, to show that
  // a wrong noise model is detected (tests/cli/montecarlo.cpp).
  auto* noise_scale_opt = sub->add_option("--noise-scale", noise_scale, "")->group("")->check(CLI::PositiveNumber);
  sub->add_flag("--json", as_json,
                "Print one JSON object (schemas/montecarlo_output.schema.json) instead of the summary");
  static std::string report_path;
  sub->add_option("--report", report_path,
                  "Also write a self-contained HTML report: heatmaps of the sample covariance against the predicted "
                  "one, and the summary (replaced atomically)")
      ->type_name("OUT.html")
      ->check(OutputPathCheck());
  static std::string shard_text, shard_output;
  static std::vector<std::string> merge_files;
  auto* shard_opt =
      sub->add_option("--shard", shard_text,
                      "Run only shard K of N (0 <= K < N): the contiguous block of trials [K N_trials / N, (K+1) "
                      "N_trials / N), their end errors written to -o FILE; imuconv montecarlo --merge joins the N "
                      "files into the whole run's output (docs/montecarlo.md)")
          ->type_name("K/N");
  auto* output_opt = sub->add_option("-o,--output", shard_output, "With --shard: the shard file (replaced atomically)")
                         ->type_name("FILE")
                         ->check(OutputPathCheck());
  auto* merge_opt =
      sub->add_option("--merge", merge_files,
                      "Join the N shard files of one run (any order; every K once) and print, and exit with, what the "
                      "whole run would have (--json, --report as for a run); the run's options come from the shards")
          ->type_name("SHARD...");
  AddPluginDirOption(*sub, ctx);
  // The options of a run or a shard, none of which a merge takes (its run is the shards').
  const std::vector<const CLI::Option*> run_only = {case_opt,     pipeline_opt,    from_opt,       to_opt,
                                                    method_opt,   trials_opt,      seed_opt,       shard_opt,
                                                    output_opt,   convention_opt,  threads_opt,    duration_opt,
                                                    noise_scale_opt};
  sub->callback([&ctx, run_only, case_opt, pipeline_opt, from_opt, to_opt, method_opt, trials_opt, seed_opt, shard_opt,
                 output_opt, merge_opt] {
    montecarlo::Result result;
    std::optional<report::ReportOutput> report_out;
    std::string report_case = case_path;
    try {
      // Which of the three forms (a run, a shard, a merge), and its options.
      const bool merging = merge_opt->count() > 0;
      if (merging) {
        for (const CLI::Option* o : run_only)
          if (o->count() > 0)
            throw Error("--merge takes the run from its shards; " + o->get_name() + " is not used with it");
      } else {
        std::string missing;
        if (case_opt->count() == 0 && pipeline_opt->count() == 0) missing = "--case (or --pipeline)";
        for (const CLI::Option* o : {method_opt, trials_opt, seed_opt})
          if (o->count() == 0) missing += (missing.empty() ? "" : ", ") + o->get_name();
        if (!missing.empty()) throw Error(missing + ": required (or --merge SHARD...)");
        if (case_opt->count() > 0 && pipeline_opt->count() > 0)
          throw Error("give the samples with one of --case CASE.json or --pipeline P.json, not both");
      }
      const std::string& input_path = pipeline_path.empty() ? case_path : pipeline_path;
      report_case = input_path;
      std::optional<std::pair<int, int>> shard;
      if (shard_opt->count() > 0) {
        try {
          const auto [index, count] = ParseShardOption(shard_text);
          shard = {static_cast<int>(index), static_cast<int>(count)};
        } catch (const UsageError& u) {
          throw Error(u.message);
        }
        if (shard_output.empty())
          throw Error("--shard K/N needs -o FILE: the shard file imuconv montecarlo --merge reads");
        if (!pipeline_path.empty())
          throw Error("--shard takes --case: a shard records its case file's digest, and a pipeline's samples are in "
                      "other files");
        if (as_json || !report_path.empty())
          throw Error("--shard writes its trials' end errors, not statistics: --json and --report go with --merge");
      } else if (output_opt->count() > 0) {
        throw Error("-o is the shard file of --shard K/N; a whole run prints its summary or --json to stdout");
      }
      // The report's destination is examined before any work (a directory or an input fails now).
      if (!report_path.empty()) {
        report_out.emplace(report_path);
        if (merging)
          for (const std::string& f : merge_files) report_out->RefuseIfSame(f, "a shard");
        else
          report_out->RefuseIfSame(input_path, pipeline_path.empty() ? "the case file" : "the pipeline file");
      }
      if (merging) {
        try {
          result = montecarlo::MergeShards(merge_files, report_case);
        } catch (const std::exception& e) {
          throw Error(std::string("--merge: ") + e.what());
        }
        if (report_out) {
          report_out->Write(report::MontecarloPage(result, {{"case", report_case}}));
          if (!ctx.quiet()) std::cerr << "wrote " << Printable(report_path) << "\n";
        }
      } else {
        // The shard file's destination too is examined before any work.
        std::optional<pipeline::OutputFile> shard_out;
        if (shard) {
          shard_out.emplace(shard_output);
          shard_out->refuse_if_same(case_path, "the case file");
        }
        if (trials > montecarlo::kMaxTrials)
          throw Error("--trials " + std::to_string(trials) + ": at most " + std::to_string(montecarlo::kMaxTrials) +
                      " (each trial's 15-dim error is kept for the statistics)");
        if (trials < montecarlo::kDim + 1)
          throw Error("--trials " + std::to_string(trials) +
                      ": need at least 16 (the sample covariance of 15-dim errors is singular below, its KL divergence "
                      "infinite)");
        Registry reg;
        std::vector<LoadIssue> issues = LoadRegistry(reg, ctx);
        for (const auto& i : issues)
          std::cerr << "imuconv: warning: " << Printable(i.file) << ": " << Printable(i.message) << "\n";

        PreintegrationMethod method;
        if (reg.has(PluginKind::Propagator, method_id))
          method = ResolvePreintegrationMethod(reg, PluginKind::Propagator, method_id);
        else if (reg.has(PluginKind::Preintegrator, method_id))
          method = ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, method_id);
        else
          throw Error("--method: unknown method " + Printable(method_id) + "; known " + KnownMethods(reg));
        const std::string conv = convention.empty() ? montecarlo::DefaultConvention(method) : convention;
        const std::string unknown = UnknownConventionMessage(reg, PluginKind::IncrementConvention, conv, issues);
        if (!unknown.empty()) throw Error("--convention: " + unknown);

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
            std::cerr << "imuconv: note: " << Printable(case_path) << ": not given, standard values used: " << list
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
        const double t_from = from_opt->count() > 0 ? from_t : samples.front().t;
        double t_to = to_opt->count() > 0 ? to_t : samples.back().t;
        if (!std::isfinite(t_from) || !std::isfinite(t_to) || !(t_from < t_to))
          throw Error("--from " + std::to_string(t_from) + " --to " + std::to_string(t_to) +
                      ": expected finite times with --from before --to");
        for (const ImuSample& smp : samples)
          if (smp.t >= t_from - 1e-9) {
            if (duration > 0) t_to = std::min(t_to, smp.t + duration);
            break;
          }
        for (const ImuSample& smp : samples)
          if (smp.t >= t_from - 1e-9 && smp.t <= t_to + 1e-9) input.samples.push_back(smp);
        if (input.samples.size() < 2)
          throw Error(Printable(input_path) + ": the interval [" + std::to_string(t_from) + ", " +
                      std::to_string(t_to) + "] s holds " + std::to_string(input.samples.size()) +
                      " samples (the samples span [" + std::to_string(samples.front().t) + ", " +
                      std::to_string(samples.back().t) + "] s); need at least two to integrate");

        montecarlo::Options options;
        options.trials = trials;
        options.seed = seed;
        options.threads = threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
        options.noise_scale = noise_scale;
        // A progress bar on stderr for a person watching: only when stderr is a terminal, never
        // with --json (a program reads that) nor with -q.
        const bool show_progress = !as_json && !ctx.quiet() && isatty(STDERR_FILENO) == 1;
        if (show_progress)
          options.progress = [](int done, int total) {
            const int width = 40, filled = static_cast<int>(static_cast<long long>(width) * done / total);
            std::cerr << "\rmontecarlo [" << std::string(filled, '#') << std::string(width - filled, '.') << "] "
                      << done << "/" << total << std::flush;
          };
        struct ClearLine {
          bool on;
          ~ClearLine() {
            if (on) std::cerr << "\r\033[K" << std::flush;
          }
        } clear_line{show_progress};
        if (shard) {
          // Its block of trials, seeded from (seed, i) as in the whole run, and what identifies the run.
          const auto [first, end] = montecarlo::ShardTrials(trials, shard->first, shard->second);
          std::vector<Vec15> errors;
          const montecarlo::Result head = montecarlo::RunTrials(reg, method, conv, input, options, first, end, errors);
          const nlohmann::json provenance = montecarlo::ShardProvenance(reg, method, head.convention, case_path);
          shard_out->refuse_if_loaded_object();
          montecarlo::WriteShard([&](std::string_view piece) { shard_out->write(piece); }, shard->first, shard->second,
                                 first, end, montecarlo::ShardRunJson(head, provenance), errors);
          std::cout.flush();
          shard_out->commit();
          if (!ctx.quiet() && !shard_out->is_stdout())
            std::cout << "wrote " << Printable(shard_output) << " (shard " << shard->first << "/" << shard->second
                      << ": trials [" << first << ", " << end << ") of " << trials << ")\n";
          ctx.exit_code = 0;
          return;
        }
        result = montecarlo::RunMonteCarlo(reg, method, conv, input, options);
        if (report_out) {
          report_out->RefuseIfLoadedObject();
          report_out->Write(report::MontecarloPage(
              result, {pipeline_path.empty() ? report::Inputs::value_type{"case", case_path}
                                             : report::Inputs::value_type{"pipeline", pipeline_path}}));
          if (!ctx.quiet()) std::cerr << "wrote " << Printable(report_path) << "\n";
        }
      }
    } catch (const std::exception& e) {
      // Nothing could be judged: neither consistent (0) nor inconsistent (1).
      ctx.exit_code = ReportFailure(e);
      return;
    }
    if (as_json)
      std::cout << montecarlo::ReportJson(result).dump(1) << "\n";
    else
      montecarlo::PrintSummary(std::cout, result);
    ctx.exit_code = result.verdict == montecarlo::Verdict::consistent ? 0 : 1;
  });
}

}  // namespace imuconv::cli
