// imuconv: IMU propagation and preintegration with conventions as plugins.
// Each subcommand is registered here and implemented in its own cmd_<name>.cpp.
#include <exception>
#include <iostream>

#include "commands.h"
#include "imuconv/plugin_kind.h"
#include "imuconv/pipeline/output_file.h"

int main(int argc, char** argv) {
  using namespace imuconv::cli;
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
  app.add_option("--plugin-dir", ctx.plugin_dirs_main,
                 "Extra plugin directory, searched before IMUCONV_PLUGIN_PATH and the built-in one (repeatable)")
      ->type_name("DIR")
      ->allow_extra_args(false);
  app.add_flag("--allow-plugin-override", ctx.allow_plugin_override,
               "Two plugins with one id: use the one earlier on the search path (a warning) instead of failing");

  // ---- subcommands (one file each) ----
  RegisterPluginsCommand(app, ctx);
  RegisterConversionCommand(app, ctx);
  RegisterConvertCommand(app, ctx);
  RegisterRunCommand(app, ctx);
  RegisterRefcaseCommand(app, ctx);
  RegisterBenchCommand(app, ctx);

  try {
    app.parse(argc, argv);  // runs the chosen subcommand's callback
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help (stdout) or the usage error (stderr)
    return code == 0 ? 0 : 2;
  } catch (const std::exception& e) {
  RegisterCheckCommand(app, ctx);
    PrintError(e.what());
    return 1;
  } catch (...) {
    PrintError("unknown failure");
    return 1;
  }
  return ctx.exit_code;
}
