// imuconv nees (--imu IMU.csv --ground-truth GT.csv --noise NOISE | --pipeline P.json [--noise
// NOISE])
// --windows L1,L2,... --method M [--convention C] [--stride S] [--json]: windows along real data,
// each propagated from the ground truth, their NEES against chi-square(9) and the factor on the
// noise densities that fits the median (docs/nees.md; the logic is apps/nees/).
// Exit code: 0 success, 2 unusable input (the message names the file and line, the JSON pointer
// or the option). There is no verdict: the factor is the answer.
#include "imuconv/cli/cmd_nees.h"

#include <memory>
#include <utility>

#include "imuconv/cli/exit_codes.h"
#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/printable.h"
#include "imuconv/report/report_output.h"
#include "judgment.h"
#include "nees.h"
#include "nees_input.h"
#include "nees_report.h"
#include "report/pages/pages.h"
#include "report_destination.h"

namespace imuconv::cli {
int RunNeesCommand(const CommandContext& ctx, const NeesCommandOptions& o) {
  if (o.pipeline_path.empty() &&
      (o.imu_path.empty() || o.ground_truth_path.empty() || o.noise_path.empty()))
    throw UsageError{"give --imu, --ground-truth and --noise, or --pipeline P.json"};
  // Each input as the report page names it, (role, path), for those given.
  const report::Inputs inputs = GivenInputs({{"imu", &o.imu_path},
                                             {"ground truth", &o.ground_truth_path},
                                             {"noise", &o.noise_path},
                                             {"pipeline", &o.pipeline_path}});
  return Judge(o.as_json, [&] {
    // The report's destination is examined before any work (a directory or an input fails now).
    ReportDestination report(o.report_path);
    for (const auto& input : inputs) report.RefuseIfSame(input.second, "the input file");
    Registry reg;
    LoadRegistryWithStateConvention(reg, ctx, o.convention);
    nees::Options options;
    options.method = o.method;
    options.convention = o.convention;
    options.window_lengths = o.windows;
    options.stride = o.stride;
    const nees::Input in = o.pipeline_path.empty()
                               ? nees::ReadEurocInput(o.imu_path, o.ground_truth_path)
                               : nees::ReadPipelineInput(o.pipeline_path);
    options.noise = nees::NoiseGivenOrInPipeline(o.noise_path, in.noise, o.pipeline_path);
    options.gravity = in.gravity;
    Judgment judgment;
    judgment.warnings = in.warnings;  // the samples' units or columns; the poses against the gyro
    PrintWarnings(judgment.warnings);
    const auto result =
        std::make_shared<const nees::Result>(nees::RunNees(reg, in.imu, in.gt, options));
    // Windows in a gap of the data are skipped, never fitted in silence.
    const std::vector<std::string> skipped = nees::SkippedWindows(*result);
    PrintWarnings(skipped);
    judgment.warnings.insert(judgment.warnings.end(), skipped.begin(), skipped.end());
    report.Write([&] { return report::NeesPage(*result, inputs); }, ctx);
    judgment.SetResult(result, nees::ReportJson, nees::PrintSummary);
    judgment.exit_code = kExitOk;  // no verdict: the factor is the answer
    return judgment;
  });
}

// The command line of imuconv nees: its description, and its flags onto the options.
static void DeclareNeesCommand(CLI::App* sub, NeesCommandOptions* o) {
  sub->description(
      "Propagate windows of real data from the ground truth and fit the "
      "noise densities' scale to their NEES");
  auto* imu_opt = AddImuCsvOption(*sub, o->imu_path);
  auto* gt_opt =
      sub->add_option("--ground-truth", o->ground_truth_path,
                      "EuRoC/ASL full-state ground truth (17 fields: time, p, q wxyz, v, bg, ba)");
  sub->add_option("--pipeline", o->pipeline_path,
                  "Instead of --imu and --ground-truth: a pipeline whose /imu (EuRoC, generic CSV "
                  "with its column map "
                  "and time unit, or inline), /ground_truth (format euroc), /noise and /gravity "
                  "are read as imuconv "
                  "run reads them (its tasks are not run)")
      ->excludes(imu_opt)
      ->excludes(gt_opt);
  AddNoiseFileOption(*sub, o->noise_path);
  sub->add_option("--windows", o->windows,
                  "Window lengths in seconds, comma-separated (e.g. 0.2,0.5,1.0)")
      ->required()
      ->delimiter(',');
  sub->add_option("--method", o->method, "A propagator id")->required();
  sub->add_option("--convention", o->convention,
                  "State convention of the error and covariance (default: left)");
  sub->add_option("--stride", o->stride,
                  "Seconds between window starts (default: each window's length)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--json", o->as_json,
                "Print one JSON object (schemas/nees_output.schema.json) instead of the table");
  AddReportOption(*sub, o->report_path,
                  "NEES per window against chi-square(9), each error component with its +-3 sigma "
                  "over time, and "
                  "the summary (replaced atomically)");
}

void RegisterNeesCommand(CLI::App& app, CommandContext& ctx) {
  AddCommand(app, ctx, "nees", DeclareNeesCommand, RunNeesCommand);
}

}  // namespace imuconv::cli
