// imuconv: IMU propagation and preintegration with conventions as plugins.
// Each subcommand is registered here and implemented in its own cmd_<name>.cpp.
#include <chrono>
#include <exception>
#include <iostream>

#include "imuconv/cli/commands.h"
#include "imuconv/cli/exit_codes.h"
#include "imuconv/pipeline/output_file.h"
#include "imuconv/pipeline/standard_descriptors.h"
#include "imuconv/plugin_kind.h"
#include "standard_output.h"
#include "usage_hint.h"

int main(int argc, char** argv) {
  using namespace imuconv::cli;
  // First of all: a closed standard descriptor is opened onto /dev/null, so that no file opened
  // later takes its number (the summary printed to "stdout" would land in the output file).
  try {
    imuconv::pipeline::OpenClosedStandardDescriptors();
  } catch (const std::exception& e) {
    PrintError(e.what());
    return 2;
  }
  // What is printed on standard output is checked at the end (CompleteStandardOutput below).
  WatchStandardOutput();
  // An interrupted run (Ctrl-C, kill, a closed terminal or pipe) removes its temporary output
  // file before dying of the signal; the previous output, if any, is untouched.
  imuconv::pipeline::RemoveTemporariesOnSignal();
  CLI::App app{
      "imuconv: IMU propagation and preintegration, with perturbation conventions, integrators and "
      "preintegrators as plugins.",
      "imuconv"};
  app.require_subcommand(1);
  // The version and the plugin ABI it loads: what a bug report and a plugin author need.
  app.set_version_flag("--version", std::string("imuconv ") + IMUCONV_VERSION + " (plugin ABI " +
                                        std::to_string(imuconv::kPluginAbiVersion) + ")");
  CommandContext ctx;
  AddPluginSearchDirOption(app, ctx.plugin_dirs_main);
  app.add_flag("--allow-plugin-override", ctx.allow_plugin_override,
               "Two plugins with one id: use the one earlier on the search path (a warning) "
               "instead of failing");
  auto* quiet = app.add_flag_callback(
      "-q,--quiet", [&ctx] { ctx.verbosity = -1; },
      "Print only results, warnings and errors (no summaries, no \"wrote\" lines)");
  auto* verbose = app.add_flag_callback(
      "-v,--verbose", [&ctx] { ctx.verbosity = 1; },
      "Also print the plugin search path, each plugin loaded and the time taken, on stderr");
  quiet->excludes(verbose);

  // ---- subcommands (one file each) ----
#define IMUCONV_REGISTER_COMMAND(Name) Register##Name##Command(app, ctx);
  IMUCONV_COMMANDS(IMUCONV_REGISTER_COMMAND)
#undef IMUCONV_REGISTER_COMMAND
  // One rule for every numeric option of every command (cli_common.cpp).
  RefuseNonFiniteNumbers(app);

  // One exit-code table for every command (exit_codes.h), under every --help.
  app.footer(kExitCodeFooter);
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    sub->footer(kExitCodeFooter);

  const auto start = std::chrono::steady_clock::now();
  try {
    app.parse(argc, argv);  // runs the chosen subcommand's callback
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0)
      return CompleteStandardOutput(app.exit(e));  // --help, --version (stdout)
    // A mistyped subcommand or flag: name it and the nearest known ones; otherwise the
    // parser's own message (a missing argument, a bad value).
    const std::string hint = UsageHint(app, argc, argv);
    if (hint.empty()) {
      app.exit(e);  // the usage error (stderr)
    } else {
      PrintError(hint);
      std::cerr << "Run with --help for more information.\n";
    }
    return kExitBadInput;
  } catch (const std::exception& e) {
    return CompleteStandardOutput(ReportFailure(e));
  } catch (...) {
    PrintError(
        "internal error: an unknown failure (a defect of imuconv or of a plugin; please report "
        "it)");
    return CompleteStandardOutput(kExitInternal);
  }
  if (ctx.verbose())
    std::cerr << "imuconv: " << app.get_subcommands().front()->get_name() << " took "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
              << " s\n";
  // What the command printed must have reached standard output, else it failed
  // (standard_output.h): checked here once, for every command.
  return CompleteStandardOutput(ctx.exit_code);
}
