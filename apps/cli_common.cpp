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
}

std::vector<LoadIssue> LoadRegistry(Registry& reg, const CommandContext& ctx, const std::vector<std::string>& extra) {
  std::vector<std::string> dirs = ctx.plugin_dirs();
  dirs.insert(dirs.end(), extra.begin(), extra.end());
  return reg.load_search_path(dirs);
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
