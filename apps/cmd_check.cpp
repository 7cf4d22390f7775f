// imuconv check MEAS.json (--case CASE.json | --pipeline P.json) [--json]: are a user's preintegrated measurements
// (increment, bias Jacobian, covariance) what propagation over the same samples gives, and if
// not, what explains them (docs/check.md; the logic is apps/check/).
// Exit code: 0 consistent, 1 inconsistent, 2 unusable input (the message names the file and
// the JSON pointer).
#include <iostream>
#include <optional>

#include "imuconv/check/check.h"
#include "imuconv/check/pipeline_task.h"
#include "imuconv/check/report.h"
#include "commands.h"
#include "exit_codes.h"
#include "imuconv/pipeline/imu_plausibility.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/printable.h"
#include "imuconv/report/report_output.h"
#include "imuconv/pipeline/measurement.h"
#include "report/pages/pages.h"

namespace imuconv::cli {

void RegisterCheckCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand(
      "check", "Check a preintegrated measurement file against propagation over a case's or a pipeline's samples");
  static std::string meas_path, case_path, pipeline_path;
  static bool as_json = false;
  sub->add_option("MEAS", meas_path,
                  "Measurements file (schemas/measurements.schema.json; any chart may be \"unknown\")")
      ->required();
  auto* case_opt = sub->add_option("--case", case_path,
                                   "Reference case with the IMU samples and noise (tests/data/reference/FORMAT.md)");
  sub->add_option("--pipeline", pipeline_path,
                  "Pipeline whose /imu and /noise are the samples and noise (read as imuconv run reads them; its "
                  "tasks are not run); the measurements' times are on its time axis")
      ->excludes(case_opt);
  // The pipeline's check tasks (`imuconv run`) are evaluated by this command's library.
  check::RegisterPipelineTask();
  sub->add_flag("--json", as_json, "Print one JSON object (schemas/check_output.schema.json) instead of the table");
  static std::string report_path;
  sub->add_option("--report", report_path,
                  "Also write a self-contained HTML report: per measurement, heatmaps of the entrywise differences "
                  "under the best explanation, and the summary (replaced atomically)")
      ->type_name("OUT.html")
      ->check(OutputPathCheck());
  AddPluginDirOption(*sub, ctx);
  sub->callback([&ctx] {
    if (case_path.empty() == pipeline_path.empty())
      throw CLI::ValidationError("give the IMU samples and noise with one of --case CASE.json or --pipeline P.json");
    check::CheckResult result;
    std::vector<std::string> imu_warnings;  // suspected units or column order of the samples
    std::optional<report::ReportOutput> report_out;
    try {
      // The report's destination is examined before any work (a directory or an input fails now).
      if (!report_path.empty()) {
        report_out.emplace(report_path);
        report_out->RefuseIfSame(meas_path, "the measurements file");
        report_out->RefuseIfSame(pipeline_path.empty() ? case_path : pipeline_path, "the input file");
      }
      Registry reg;
      for (const auto& i : LoadRegistry(reg, ctx))
        std::cerr << "imuconv: warning: " << Printable(i.file) << ": " << Printable(i.message) << "\n";
      if (report_out) report_out->RefuseIfLoadedObject();
      std::optional<std::int64_t> origin_ns;  // --pipeline: the data's time axis
      const check::CaseInput input = pipeline_path.empty()
                                         ? check::ReadCaseFile(case_path)
                                         : check::ReadPipelineInput(pipeline::Pipeline::Load(pipeline_path), origin_ns);
      imu_warnings = pipeline::ImuPlausibilityWarnings(input.samples, pipeline_path.empty() ? case_path : pipeline_path);
      PrintWarnings(imu_warnings);
      const auto ms = pipeline::ReadDeclaredMeasurementFile(meas_path, reg, origin_ns);
      result = check::RunCheck(reg, input, ms, meas_path);
      if (report_out) {
        report_out->Write(
            report::CheckPage(result, {{"measurements", meas_path},
                                       pipeline_path.empty() ? report::Inputs::value_type{"case", case_path}
                                                             : report::Inputs::value_type{"pipeline", pipeline_path}}));
        if (!ctx.quiet()) std::cerr << "wrote " << Printable(report_path) << "\n";
      }
    } catch (const std::exception& e) {
      // Nothing could be checked: neither consistent (0) nor inconsistent (1).
      ctx.exit_code = ReportFailure(e);
      return;
    }
    if (as_json)
      std::cout << WithWarnings(check::ReportJson(result), imu_warnings).dump(1) << "\n";
    else
      check::PrintTable(std::cout, result);
    ctx.exit_code = result.verdict == check::Verdict::consistent ? 0 : 1;
  });
}

}  // namespace imuconv::cli
