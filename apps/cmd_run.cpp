// imuconv run PIPELINE.json [-o OUT.json]: runs a JSON pipeline.
#include <iostream>

#include "commands.h"
#include "imuconv/pipeline/output_file.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/printable.h"

namespace imuconv::cli {
namespace {

struct Options {
  std::string pipeline, output;
  bool quiet = false, every_row = false;
  unsigned threads = 0;
};

int Run(const CommandContext& ctx, const Options& o) {
  const pipeline::Pipeline p = pipeline::Pipeline::Load(o.pipeline);
  std::string out = o.output;
  if (out.empty() && p.output_path()) out = *p.output_path();
  if (out.empty()) out = "-";
  // The destination is examined before any work (nothing is created yet): what kind of file
  // it is, and that it is none of the files the run reads or loads.
  pipeline::OutputFile file(out);
  const std::vector<std::string> inputs = p.input_files();
  for (std::size_t i = 0; i < inputs.size(); ++i)
    file.refuse_if_same(inputs[i], inputs[i] == p.file() ? "the pipeline" : "the input file");
  pipeline::RunOptions ro;
  ro.plugin_dirs = ctx.plugin_dirs();
  ro.allow_plugin_override = ctx.allow_plugin_override;
  ro.log = &std::cerr;
  ro.summary = o.quiet ? nullptr : (file.is_stdout() ? &std::cerr : &std::cout);
  ro.threads = o.threads;
  ro.every_row = o.every_row;
  // The runner loads the plugins and hands text to the sink only once the plugins, the data and
  // the times have been checked. Then, before a file's temporary is created, the destination
  // must not be a plugin (or library) the run has loaded. The text for a device, a FIFO or
  // stdout is held until the run has succeeded: a failing run writes nothing anywhere.
  bool first = true;
  pipeline::RunToText(p, ro, [&](std::string_view s) {
    if (first) file.refuse_if_loaded_object();
    first = false;
    file.write(s);
  });
  std::cout.flush();
  file.commit();
  if (!o.quiet && !file.is_stdout()) std::cout << "\nwrote " << Printable(out) << "\n";
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
  sub->add_option("-o,--output", o.output,
                  "Output file: a regular file is replaced atomically (keeping its permissions; a symbolic link is "
                  "followed to it); a device or FIFO is written through; '-' is stdout. Never one of the inputs")
      ->type_name("OUT.json");
  sub->add_flag("-q,--quiet", o.quiet, "Do not print the summary");
  sub->add_flag("--table", o.every_row,
                "Print every row of a step table (by default one of more than 50 steps shows its totals and worst steps)");
  sub->add_option("-j,--threads", o.threads,
                  "Threads for independent intervals (0 = every core, the default; 1 = serial). The output is the "
                  "same, byte for byte, for any number")
      ->type_name("N");
  AddPluginDirOption(*sub, ctx);
  sub->callback([&ctx] { ctx.exit_code = Run(ctx, o); });
}

}  // namespace imuconv::cli
