// imuconv plugins [--json]: every plugin found on the search path, and what failed to load.
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"

namespace imuconv::cli {
namespace {

std::string JoinBlocks(const std::vector<std::string>& b) {
  std::string s;
  for (const auto& x : b) s += (s.empty() ? "" : ",") + x;
  return s.empty() ? "-" : "[" + s + "]";
}

int Run(const CommandContext& ctx, bool as_json) {
  Registry reg;
  const auto issues = LoadRegistry(reg, ctx);
  const auto path = Registry::search_path(ctx.plugin_dirs());
  if (as_json) {
    nlohmann::json j;
    j["search_path"] = path;
    j["plugins"] = nlohmann::json::array();
    for (const auto& p : reg.plugins()) {
      nlohmann::json e = {{"id", p.id},           {"kind", KindName(p.kind)}, {"file", p.file},
                          {"version", p.version}, {"summary", p.summary},   {"blocks", p.blocks}};
      if (!p.native_convention.empty()) e["native_convention"] = p.native_convention;
      if (!p.jacobian_convention.empty()) e["jacobian_convention"] = p.jacobian_convention;
      if (p.kind == PluginKind::StateConvention || p.kind == PluginKind::PreintConvention)
        e["analytic_jacobians"] = p.analytic_jacobians;
      j["plugins"].push_back(e);
    }
    j["load_errors"] = nlohmann::json::array();
    for (const auto& i : issues) j["load_errors"].push_back({{"file", i.file}, {"message", i.message}});
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << "search path:\n";
  for (const auto& d : path) std::cout << "  " << d << "\n";
  for (PluginKind kind : {PluginKind::StateConvention, PluginKind::PreintConvention, PluginKind::Propagator,
                          PluginKind::Preintegrator}) {
    std::cout << "\n" << KindName(kind) << ":\n";
    bool any = false;
    for (const auto& p : reg.plugins()) {
      if (p.kind != kind) continue;
      any = true;
      std::cout << "  " << std::left << std::setw(24) << p.id << " " << std::setw(8) << p.version << " ";
      if (kind == PluginKind::Propagator)
        std::cout << std::setw(34) << ("native: " + p.native_convention);
      else if (kind == PluginKind::Preintegrator)
        std::cout << std::setw(34) << ("cov: " + p.native_convention + ", J: " + p.jacobian_convention);
      else
        std::cout << std::setw(34) << JoinBlocks(p.blocks);
      std::cout << " " << p.file << "\n";
    }
    if (!any) std::cout << "  (none)\n";
  }
  if (!issues.empty()) {
    std::cout << "\nload errors:\n";
    for (const auto& i : issues) std::cout << "  " << i.file << ": " << i.message << "\n";
  }
  return 0;
}

}  // namespace

void RegisterPluginsCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand("plugins", "List the plugins found (id, kind, file, block order, version) and load errors");
  static bool as_json = false;
  sub->add_flag("--json", as_json, "Print JSON instead of a table");
  AddPluginDirOption(*sub, ctx);
  sub->callback([&ctx] { ctx.exit_code = Run(ctx, as_json); });
}

}  // namespace imuconv::cli
