#include <iostream>

#include "commands.h"

namespace imuconv::cli {

std::vector<std::string> CommandContext::plugin_dirs() const {
  std::vector<std::string> d = plugin_dirs_main;
  d.insert(d.end(), plugin_dirs_sub.begin(), plugin_dirs_sub.end());
  return d;
}

void AddPluginDirOption(CLI::App& sub, CommandContext& ctx) {
  sub.add_option("--plugin-dir", ctx.plugin_dirs_sub,
                 "Extra plugin directory, searched before IMUCONV_PLUGIN_PATH and the built-in one (repeatable)")
      ->type_name("DIR")
      ->allow_extra_args(false);
  sub.add_flag("--allow-plugin-override", ctx.allow_plugin_override,
               "Let a plugin earlier on the search path replace one with the same id (a warning names both files); "
               "without it a duplicate id is an error");
}

std::vector<LoadIssue> LoadRegistry(Registry& reg, const CommandContext& ctx, const std::vector<std::string>& extra) {
  std::vector<std::string> dirs = ctx.plugin_dirs();
  dirs.insert(dirs.end(), extra.begin(), extra.end());
  LoadOptions options;
  options.allow_override = ctx.allow_plugin_override;
  return reg.load_search_path(dirs, options);
}

void PrintError(const std::string& message) {
  std::string out = "imuconv: error: ";
  for (char c : message) {
    out += c;
    if (c == '\n') out += "  ";
  }
  std::cerr << out << "\n";
}

}  // namespace imuconv::cli
