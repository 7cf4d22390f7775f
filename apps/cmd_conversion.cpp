// imuconv conversion --from A --to B --state STATE.json [--json]: the 15x15 Jacobian
// d dx_B / d dx_A of a state-convention change at a state, with block labels.
#include <iostream>
#include <memory>

#include "imuconv/cli/commands.h"
#include "imuconv/cli/exit_codes.h"
#include "imuconv/cli/non_finite_result.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv/printable.h"

namespace imuconv::cli {
namespace {

struct ConversionOptions {
  std::string from, to, state;
  bool as_json = false;
};

// The command line of imuconv conversion: its description, and its flags onto the options.
void DeclareConversionCommand(CLI::App* sub, ConversionOptions* o) {
  sub->description(
      "Print the 15x15 Jacobian d dx_B / d dx_A between two state conventions at a state");
  sub->add_option("--from", o->from, "State convention id A (e.g. left)")
      ->required()
      ->type_name("A");
  sub->add_option("--to", o->to, "State convention id B (e.g. gtsam_navstate)")
      ->required()
      ->type_name("B");
  sub->add_option("--state", o->state, "State file: {\"p\", \"q_wxyz\", \"v\", \"bg\", \"ba\"}")
      ->required()
      ->type_name("STATE.json");
  sub->add_flag("--json", o->as_json,
                "Print JSON (the matrix with its row and column conventions and blocks)");
}

int ExecuteConversion(const CommandContext& ctx, const ConversionOptions& o) {
  Registry reg;
  const auto issues = LoadRegistry(reg, ctx);
  for (const auto& id : {o.from, o.to}) {
    const std::string unknown =
        UnknownConventionMessage(reg, PluginKind::StateConvention, id, issues);
    if (unknown.empty()) continue;
    PrintError(unknown);
    return kExitBadInput;
  }
  const ImuState x = pipeline::ReadStateFile(o.state);
  const Mat15 J = reg.conversion(o.from, o.to, x);
  const std::string non_finite =
      NonFiniteResultMessage(J, "conversion", "jacobian", o.from, o.to, "state");
  if (!non_finite.empty()) {
    PrintError(non_finite);
    return kExitBadInput;
  }
  const auto bf = pipeline::Blocks(reg, PluginKind::StateConvention, o.from);
  const auto bt = pipeline::Blocks(reg, PluginKind::StateConvention, o.to);
  if (o.as_json) {
    nlohmann::json j = {{"from", o.from},
                        {"to", o.to},
                        {"state", pipeline::StateToJson(x)},
                        {"jacobian", pipeline::MixedMatrixToJson(J, o.to, bt, o.from, bf)}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << "d dx[" << o.to << "] / d dx[" << o.from << "] at the state in " << o.state
            << "\nrows: " << o.to << " blocks, columns: " << o.from << " blocks\n\n";
  PrintLabelledMatrix(std::cout, J, bt, bf);
  return 0;
}

}  // namespace

void RegisterConversionCommand(CLI::App& app, CommandContext& ctx) {
  AddCommand(app, ctx, "conversion", DeclareConversionCommand, ExecuteConversion);
}

}  // namespace imuconv::cli
