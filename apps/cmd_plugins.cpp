// imuconv plugins [--json]: every plugin found on the search path, and what failed to load.
// imuconv plugins --check DIR: each plugin file of DIR loaded and exercised in a child process.
//
// Every path, id, version and message is printed through Printable (SafeText for messages
// already built with Quoted), so a file name with a newline cannot fake a line of output.
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "imuconv/cli/commands.h"
#include "imuconv/printable.h"
#include "plugin_check.h"

namespace imuconv::cli {
namespace {

struct PluginsOptions {
  bool as_json = false;
  std::vector<std::string> check_dirs;
  double check_timeout = 20.0;
};

std::string JoinBlocks(const std::vector<std::string>& b) {
  std::string s;
  for (const auto& x : b) s += (s.empty() ? "" : ",") + Printable(x);
  return s.empty() ? "-" : "[" + s + "]";
}

int List(const CommandContext& ctx, bool as_json) {
  Registry reg;
  const auto issues = LoadRegistry(reg, ctx);
  const auto path = Registry::search_path(ctx.plugin_dirs());
  if (as_json) {
    nlohmann::json j;
    j["search_path"] = nlohmann::json::array();
    for (const auto& d : path) j["search_path"].push_back(Printable(d));
    j["plugins"] = nlohmann::json::array();
    for (const auto& p : reg.plugins()) {
      nlohmann::json blocks = nlohmann::json::array();
      for (const auto& b : p.blocks) blocks.push_back(Printable(b));
      nlohmann::json e = {{"id", Printable(p.id)},           {"kind", KindName(p.kind)},
                          {"file", Printable(p.file)},       {"version", Printable(p.version)},
                          {"summary", Printable(p.summary)}, {"blocks", blocks}};
      if (!p.native_convention.empty()) e["native_convention"] = Printable(p.native_convention);
      if (!p.jacobian_convention.empty())
        e["jacobian_convention"] = Printable(p.jacobian_convention);
      if (p.kind == PluginKind::StateConvention || p.kind == PluginKind::IncrementConvention)
        e["analytic_jacobians"] = p.analytic_jacobians;
      if (p.kind == PluginKind::Residual) e["degrees_of_freedom"] = p.degrees_of_freedom;
      j["plugins"].push_back(e);
    }
    j["load_errors"] = nlohmann::json::array();
    j["overridden"] = nlohmann::json::array();
    for (const auto& i : issues)
      j[i.overridden ? "overridden" : "load_errors"].push_back(
          {{"file", Printable(i.file)}, {"message", SafeText(i.message)}});
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << "search path:\n";
  for (const auto& d : path) std::cout << "  " << Printable(d) << "\n";
  for (PluginKind kind : kPluginKinds) {
    std::cout << "\n" << KindName(kind) << ":\n";
    bool any = false;
    for (const auto& p : reg.plugins()) {
      if (p.kind != kind) continue;
      any = true;
      std::cout << "  " << std::left << std::setw(24) << Printable(p.id) << " " << std::setw(8)
                << Printable(p.version) << " ";
      if (kind == PluginKind::Propagator)
        std::cout << std::setw(34) << ("native: " + Printable(p.native_convention));
      else if (kind == PluginKind::Preintegrator)
        std::cout << std::setw(34)
                  << ("cov: " + Printable(p.native_convention) +
                      ", J: " + Printable(p.jacobian_convention));
      else if (kind == PluginKind::Residual)
        std::cout << std::setw(34)
                  << ("increment: " + Printable(p.native_convention) +
                      ", dof: " + std::to_string(p.degrees_of_freedom));
      else
        std::cout << std::setw(34) << JoinBlocks(p.blocks);
      std::cout << " " << Printable(p.file) << "\n";
    }
    if (!any) std::cout << "  (none)\n";
  }
  for (const bool overridden : {true, false}) {
    bool header = false;
    for (const auto& i : issues) {
      if (i.overridden != overridden) continue;
      if (!header)
        std::cout << (overridden ? "\noverridden (--allow-plugin-override):\n"
                                 : "\nload errors:\n");
      header = true;
      std::cout << "  " << Printable(i.file) << ": " << SafeText(i.message) << "\n";
    }
  }
  return 0;
}

// Never loads a plugin in this process: each file is checked by CheckPluginInChild.
int Check(const PluginsOptions& o) {
  std::vector<PluginCheck> results;
  std::vector<std::pair<std::string, std::string>> dir_problems;  // dir, message
  for (const auto& dir : o.check_dirs) {
    std::vector<std::string> files;
    try {
      files = PluginFilesIn(dir);
    } catch (const Error& e) {
      dir_problems.emplace_back(dir, e.what());
      continue;
    }
    if (files.empty())
      dir_problems.emplace_back(dir, "no imuconv_plugin_*.so file in " + Quoted(dir));
    if (!o.as_json)
      std::cout << "checking " << files.size() << " plugin file(s) in " << Quoted(dir)
                << ", each in a child process (timeout " << o.check_timeout << " s)\n"
                << std::flush;
    for (const auto& f : files) {
      results.push_back(CheckPluginInChild(f, o.check_timeout));
      if (!o.as_json)
        std::cout << "  " << Printable(f) << ": " << results.back().message << "\n" << std::flush;
    }
  }
  std::size_t failed = 0;
  for (const auto& r : results) failed += r.outcome != PluginCheck::Outcome::Ok;
  const bool all_ok = failed == 0 && dir_problems.empty();
  if (o.as_json) {
    nlohmann::json j;
    j["checked"] = nlohmann::json::array();
    for (const auto& r : results)
      j["checked"].push_back({{"file", Printable(r.file)},
                              {"result", OutcomeName(r.outcome)},
                              {"message", r.message}});
    j["directory_errors"] = nlohmann::json::array();
    for (const auto& [d, m] : dir_problems)
      j["directory_errors"].push_back({{"dir", Printable(d)}, {"message", SafeText(m)}});
    j["ok"] = all_ok;
    std::cout << j.dump(2) << "\n";
  } else {
    for (const auto& [d, m] : dir_problems) std::cout << "  " << SafeText(m) << "\n";
    if (all_ok)
      std::cout << "all " << results.size() << " plugin file(s) passed the check\n";
    else
      std::cout << failed << " of " << results.size() << " plugin file(s) failed the check"
                << (dir_problems.empty() ? ""
                                         : ", and " + std::to_string(dir_problems.size()) +
                                               " directory(ies) could not be checked")
                << "\n";
  }
  return all_ok ? 0 : 1;
}

// The list, or with --check the checks.
int RunPlugins(const CommandContext& ctx, const PluginsOptions& o) {
  return o.check_dirs.empty() ? List(ctx, o.as_json) : Check(o);
}

// The command line of imuconv plugins: its description, and its flags onto the options.
void DeclarePluginsCommand(CLI::App* sub, PluginsOptions* o) {
  sub->description(
      "List the plugins found (id, kind, file, block order, version) "
      "and load errors; or, with --check DIR, load "
      "and exercise each plugin file of DIR in a child process and "
      "report which ones fail, crash or hang");
  sub->add_flag("--json", o->as_json, "Print JSON instead of a table");
  sub->add_option("--check", o->check_dirs,
                  "Check every imuconv_plugin_*.so in DIR, each in its own child process "
                  "(repeatable); exit status 1 "
                  "if any fails. The search path is not loaded")
      ->type_name("DIR")
      ->allow_extra_args(false);
  sub->add_option("--check-timeout", o->check_timeout,
                  "Seconds each plugin file may take under --check (default 20)")
      ->type_name("SECONDS")
      ->check(CLI::Range(0.1, 3600.0));
}

}  // namespace

void RegisterPluginsCommand(CLI::App& app, CommandContext& ctx) {
  AddCommand(app, ctx, "plugins", DeclarePluginsCommand, RunPlugins);
}

}  // namespace imuconv::cli
