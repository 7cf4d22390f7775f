// imuconv check MEAS.json (--case CASE.json | --pipeline P.json) [--json]: are a user's
// preintegrated measurements (increment, bias Jacobian, covariance) what propagation over the same
// samples gives, and if not, what explains them (docs/check.md; the logic is apps/check/). Exit
// code: 0 consistent, 1 inconsistent, 2 unusable input (the message names the file and the JSON
// pointer).
#include "imuconv/cli/cmd_check.h"

#include <memory>
#include <optional>

#include "imuconv/check/check.h"
#include "imuconv/check/pipeline_task.h"
#include "imuconv/check/report.h"
#include "imuconv/cli/exit_codes.h"
#include "imuconv/pipeline/imu_plausibility.h"
#include "imuconv/pipeline/measurement.h"
#include "imuconv/pipeline/pipeline.h"
#include "judgment.h"
#include "report/pages/pages.h"
#include "report_destination.h"

namespace imuconv::cli {

int RunCheckCommand(const CommandContext& ctx, const CheckCommandOptions& o) {
  if (o.case_path.empty() == o.pipeline_path.empty())
    throw UsageError{
        "give the IMU samples and noise with one of --case CASE.json or --pipeline P.json"};
  const bool from_case = o.pipeline_path.empty();
  const std::string& samples_path = from_case ? o.case_path : o.pipeline_path;
  return Judge(o.as_json, [&] {
    // The report's destination is examined before any work (a directory or an input fails now).
    ReportDestination report(o.report_path);
    report.RefuseIfSame(o.measurements, "the measurements file");
    report.RefuseIfSame(samples_path, "the input file");
    Registry reg;
    PrintLoadIssues(LoadRegistry(reg, ctx));
    report.RefuseIfLoadedObject();
    std::optional<std::int64_t> origin_ns;  // --pipeline: the data's time axis
    const check::CaseInput input =
        from_case ? check::ReadCaseFile(o.case_path)
                  : check::ReadPipelineInput(pipeline::Pipeline::Load(o.pipeline_path), origin_ns);
    Judgment judgment;
    judgment.warnings =
        pipeline::ImuPlausibilityWarnings(input.samples, samples_path);  // units, column order
    PrintWarnings(judgment.warnings);
    const auto ms = pipeline::ReadDeclaredMeasurementFile(o.measurements, reg, origin_ns);
    const auto result =
        std::make_shared<const check::CheckResult>(check::RunCheck(reg, input, ms, o.measurements));
    report.Write(
        [&] {
          return report::CheckPage(*result, {{"measurements", o.measurements},
                                             {from_case ? "case" : "pipeline", samples_path}});
        },
        ctx);
    judgment.SetResult(result, check::ReportJson, check::PrintTable);
    judgment.exit_code =
        result->verdict == check::Verdict::consistent ? kExitOk : kExitInconsistent;
    return judgment;
  });
}

// The command line of imuconv check: its description, and its flags onto the options.
static void DeclareCheckCommand(CLI::App* sub, CheckCommandOptions* o) {
  sub->description(
      "Check a preintegrated measurement file against propagation over "
      "a case's or a pipeline's samples");
  sub->add_option(
         "MEAS", o->measurements,
         "Measurements file (schemas/measurements.schema.json; any chart may be \"unknown\")")
      ->required();
  auto* case_opt = sub->add_option(
      "--case", o->case_path,
      "Reference case with the IMU samples and noise (tests/data/reference/FORMAT.md)");
  sub->add_option("--pipeline", o->pipeline_path,
                  "Pipeline whose /imu and /noise are the samples and noise (read as imuconv run "
                  "reads them; its "
                  "tasks are not run); the measurements' times are on its time axis")
      ->excludes(case_opt);
  // The pipeline's check tasks (`imuconv run`) are evaluated by this command's library.
  check::RegisterPipelineTask();
  sub->add_flag("--json", o->as_json,
                "Print one JSON object (schemas/check_output.schema.json) instead of the table");
  AddReportOption(
      *sub, o->report_path,
      "per measurement, heatmaps of the entrywise differences under the best explanation, and the "
      "summary (replaced atomically)");
}

void RegisterCheckCommand(CLI::App& app, CommandContext& ctx) {
  AddCommand(app, ctx, "check", DeclareCheckCommand, RunCheckCommand);
}

}  // namespace imuconv::cli
