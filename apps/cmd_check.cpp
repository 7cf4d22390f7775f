// imuconv check MEAS.json --case CASE.json [--json]: are a user's preintegrated measurements
// (increment, bias Jacobian, covariance) what propagation over the same samples gives, and if
// not, what explains them (docs/check.md; the logic is apps/check/).
// Exit code: 0 consistent, 1 inconsistent, 2 unusable input (the message names the file and
// the JSON pointer).
#include <iostream>

#include "check/check.h"
#include "check/report.h"
#include "commands.h"
#include "imuconv/printable.h"
#include "pipeline/src/forms/measurement.h"

namespace imuconv::cli {

void RegisterCheckCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub =
      app.add_subcommand("check", "Check a preintegrated measurement file against propagation over a case's samples");
  static std::string meas_path, case_path;
  static bool as_json = false;
  sub->add_option("MEAS", meas_path,
                  "Measurements file (schemas/measurements.schema.json; any chart may be \"unknown\")")
      ->required();
  sub->add_option("--case", case_path, "Reference case with the IMU samples and noise (tests/data/reference/FORMAT.md)")
      ->required();
  sub->add_flag("--json", as_json, "Print one JSON object (schemas/check_output.schema.json) instead of the table");
  AddPluginDirOption(*sub, ctx);
  sub->callback([&ctx] {
    check::CheckResult result;
    try {
      Registry reg;
      for (const auto& i : LoadRegistry(reg, ctx))
        std::cerr << "imuconv: warning: " << Printable(i.file) << ": " << Printable(i.message) << "\n";
      const check::CaseInput input = check::ReadCaseFile(case_path);
      const auto ms = pipeline::ReadDeclaredMeasurementFile(meas_path, reg);
      result = check::RunCheck(reg, input, ms, meas_path);
    } catch (const std::exception& e) {
      // Nothing could be checked: neither consistent (0) nor inconsistent (1).
      PrintError(e.what());
      ctx.exit_code = 2;
      return;
    }
    if (as_json)
      std::cout << check::ReportJson(result).dump(1) << "\n";
    else
      check::PrintTable(std::cout, result);
    ctx.exit_code = result.verdict == check::Verdict::consistent ? 0 : 1;
  });
}

}  // namespace imuconv::cli
