// imuconv run PIPELINE.json [-o OUT.json]: runs a JSON pipeline.
#include <iostream>

#include "commands.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/pipeline.h"

namespace imuconv::cli {
namespace {

struct Options {
  std::string pipeline, output;
  bool quiet = false;
  unsigned threads = 0;
};

int Run(const CommandContext& ctx, const Options& o) {
  const pipeline::Pipeline p = pipeline::Pipeline::Load(o.pipeline);
  std::string out = o.output;
  if (out.empty() && p.output_path()) out = *p.output_path();
  const bool to_stdout = out.empty() || out == "-";
  pipeline::RunOptions ro;
  ro.plugin_dirs = ctx.plugin_dirs();
  ro.log = &std::cerr;
  ro.summary = o.quiet ? nullptr : (to_stdout ? &std::cerr : &std::cout);
  ro.threads = o.threads;
  if (to_stdout) {
    // Held until the run has succeeded: a failing run prints no partial document.
    std::string text;
    pipeline::RunToText(p, ro, [&](std::string_view s) { text.append(s.data(), s.size()); });
    std::cout << text << std::flush;
  } else {
    // Streamed into a temporary next to the output, renamed over it once complete.
    pipeline::AtomicFile file(out);
    pipeline::RunToText(p, ro, [&](std::string_view s) { file.write(s); });
    file.commit();
    if (!o.quiet) std::cout << "\nwrote " << out << "\n";
  }
  return 0;
}

}  // namespace

void RegisterRunCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand(
      "run",
      "Run a JSON pipeline (schemas/pipeline.schema.json). The result JSON goes to -o, else to the pipeline's "
      "\"output\", else to stdout; the summary goes to stdout (stderr when the JSON does). A failing run writes "
      "nothing.");
  static Options o;
  sub->add_option("pipeline", o.pipeline, "Pipeline file")->required()->type_name("PIPELINE.json");
  sub->add_option("-o,--output", o.output, "Output file (written atomically; '-' for stdout)")->type_name("OUT.json");
  sub->add_flag("-q,--quiet", o.quiet, "Do not print the summary");
  sub->add_option("-j,--threads", o.threads,
                  "Threads for independent intervals (0 = every core, the default; 1 = serial). The output is the "
                  "same, byte for byte, for any number")
      ->type_name("N");
  AddPluginDirOption(*sub, ctx);
  sub->callback([&ctx] { ctx.exit_code = Run(ctx, o); });
}

}  // namespace imuconv::cli
