// imuconv refcase CASE.json -o OUT.json: runs a reference case (tests/data/reference/FORMAT.md)
// through the ordinary bridge operations and writes its results in the layout of the GTSAM
// reference files, so the two can be compared entry by entry.
#include <iostream>

#include "commands.h"
#include "imuconv/pipeline/json_check.h"
#include "imuconv/pipeline/json_io.h"
#include "refcase.h"

namespace imuconv::cli {

void RegisterRefcaseCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand("refcase", "Run a reference case and write results in the GTSAM reference layout");
  static std::string case_path, out_path;
  sub->add_option("CASE", case_path, "Case file (format: tests/data/reference/FORMAT.md)")->required();
  sub->add_option("-o,--output", out_path, "Output JSON (written atomically)")->required();
  AddPluginDirOption(*sub, ctx);
  sub->callback([&ctx] {
    Registry reg;
    for (const auto& i : LoadRegistry(reg, ctx)) std::cerr << "imuconv: warning: " << i.file << ": " << i.message << "\n";
    const nlohmann::json c = pipeline::ParseJsonFile(case_path);
    nlohmann::json out;
    try {
      out = refcase::Run(reg, c);
    } catch (const Error& e) {
      throw Error(case_path + ": " + e.what());
    }
    pipeline::WriteFileAtomically(out_path, out.dump(1) + "\n");
    ctx.exit_code = 0;
  });
}

}  // namespace imuconv::cli
