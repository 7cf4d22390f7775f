// imuconv refcase CASE.json -o OUT.json: runs a reference case (tests/data/reference/FORMAT.md)
// through the ordinary bridge operations and writes its results in the layout of the GTSAM
// reference files, so the two can be compared entry by entry. With --anchor NAME it writes
// instead the computed fields of another system's anchor files (refcase/anchor.h).
#include <iostream>

#include "anchor.h"
#include "imuconv/cli/commands.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/pipeline/output_file.h"
#include "imuconv/printable.h"
#include "refcase.h"

namespace imuconv::cli {

void RegisterRefcaseCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand(
      "refcase", "Run a reference case and write results in the GTSAM reference layout");
  static std::string case_path, out_path, anchor;
  sub->add_option("CASE", case_path, "Case file (format: tests/data/reference/FORMAT.md)")
      ->required();
  sub->add_option("--anchor", anchor,
                  "Write instead the computed fields of tests/data/reference/anchors/NAME/ "
                  "(vins-fusion, basalt, "
                  "openvins), computed by imuconv with that system's input conventions")
      ->check(CLI::IsMember(refcase::AnchorNames()));
  sub->add_option("-o,--output", out_path,
                  "Output JSON: a regular file is replaced atomically (a symbolic link is followed "
                  "to it); a device or "
                  "FIFO is written through; '-' is stdout. Never the case file")
      ->required()
      ->check(OutputPathCheck());
  AddPluginDirOption(*sub, ctx);
  sub->callback([&ctx] {
    // The destination is examined first (nothing is created): its kind, and that it is neither
    // the case nor a plugin. The result is written only once it has been computed and checked.
    pipeline::OutputFile file(out_path);
    file.refuse_if_same(case_path, "the case file");
    Registry reg;
    PrintLoadIssues(LoadRegistry(reg, ctx));
    for (const auto& info : reg.plugins())
      if (info.file != "built-in") file.refuse_if_same(info.file, "the plugin");
    const nlohmann::json c = pipeline::ParseJsonFile(case_path);
    nlohmann::json out;
    try {
      out = anchor.empty() ? refcase::Run(reg, c) : refcase::RunAnchor(reg, c, anchor);
    } catch (const std::exception& e) {
      throw Error(Printable(case_path) + ": " + e.what());
    }
    file.write(out.dump(1) + "\n");
    file.commit();
    ctx.exit_code = 0;
  });
}

}  // namespace imuconv::cli
