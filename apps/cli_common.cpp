#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <new>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "imuconv/cli/commands.h"
#include "imuconv/cli/exit_codes.h"
#include "imuconv/did_you_mean.h"
#include "imuconv/printable.h"

namespace imuconv::cli {

std::vector<std::string> CommandContext::plugin_dirs() const {
  std::vector<std::string> d = plugin_dirs_main;
  d.insert(d.end(), plugin_dirs_sub.begin(), plugin_dirs_sub.end());
  return d;
}

void SetCommandAction(CLI::App& sub, CommandContext& ctx, std::function<int()> run) {
  sub.callback([&ctx, run = std::move(run)] {
    try {
      ctx.exit_code = run();
    } catch (const UsageError& e) {
      throw CLI::ValidationError(e.message);
    }
  });
}

CLI::Validator OutputPathCheck() {
  return CLI::Validator(
      [](std::string& path) {
        return path.empty() ? std::string(
                                  "the output path is empty (an unset shell variable?); expected a "
                                  "file name, "
                                  "or '-' for standard output")
                            : std::string();
      },
      "", "OUTPUT");
}

CLI::Option* AddImuCsvOption(CLI::App& sub, std::string& path) {
  return sub.add_option("--imu", path,
                        "EuRoC/ASL IMU CSV (#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z)");
}

CLI::Option* AddNoiseFileOption(CLI::App& sub, std::string& path) {
  return sub.add_option("--noise", path,
                        "The four noise densities: a JSON noise object (or a pipeline holding "
                        "one), or a Kalibr imu.yaml (.yaml/.yml, any case); with --pipeline, "
                        "replaces its /noise");
}

void AddPluginSearchDirOption(CLI::App& app, std::vector<std::string>& dirs) {
  app.add_option("--plugin-dir", dirs,
                 "Extra plugin directory, searched before IMUCONV_PLUGIN_PATH and the built-in one "
                 "(repeatable)")
      ->type_name("DIR")
      ->allow_extra_args(false);
}

void AddPluginDirOption(CLI::App& sub, CommandContext& ctx) {
  AddPluginSearchDirOption(sub, ctx.plugin_dirs_sub);
  sub.add_flag("--allow-plugin-override", ctx.allow_plugin_override,
               "Let a plugin earlier on the search path replace one with the same id (a warning "
               "names both files); "
               "without it a duplicate id is an error");
}

std::vector<LoadIssue> LoadRegistry(Registry& reg, const CommandContext& ctx,
                                    const std::vector<std::string>& extra) {
  std::vector<std::string> dirs = ctx.plugin_dirs();
  dirs.insert(dirs.end(), extra.begin(), extra.end());
  LoadOptions options;
  options.allow_override = ctx.allow_plugin_override;
  PrintSearchPath(ctx, dirs);
  std::vector<LoadIssue> issues = reg.load_search_path(dirs, options);
  if (ctx.verbose())
    for (const auto& p : reg.plugins())
      std::cerr << "imuconv: loaded " << KindName(p.kind) << " " << Printable(p.id) << " "
                << Printable(p.version) << " from " << Printable(p.file) << "\n";
  return issues;
}

void PrintLoadIssues(const std::vector<LoadIssue>& issues) {
  for (const auto& i : issues)
    std::cerr << "imuconv: warning: " << Printable(i.file) << ": " << Printable(i.message) << "\n";
}

void PrintSearchPath(const CommandContext& ctx, const std::vector<std::string>& dirs) {
  if (!ctx.verbose()) return;
  std::cerr << "imuconv: plugin search path:";
  for (const auto& d : Registry::search_path(dirs)) std::cerr << " " << Printable(d);
  if (Registry::has_compiled_in()) std::cerr << " (the built-in directory's plugins compiled in)";
  std::cerr << "\n";
}

std::pair<unsigned, unsigned> ParseShardOption(const std::string& text) {
  const auto slash = text.find('/');
  const auto number = [](std::string_view s, unsigned& v) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size();
  };
  unsigned index = 0, count = 0;
  const std::string_view t(text);
  if (slash == std::string::npos || !number(t.substr(0, slash), index) ||
      !number(t.substr(slash + 1), count) || count == 0 || index >= count)
    throw UsageError{"--shard: expected K/N with 0 <= K < N (e.g. 0/4), found '" + Printable(text) +
                     "'"};
  return {index, count};
}

void RefuseNonFiniteNumbers(CLI::App& app) {
  for (CLI::Option* opt : app.get_options([](CLI::Option*) { return true; })) {
    if (opt->get_type_size() == 0) continue;  // a flag takes no value
    // CLI11 names the option in front of the message, except a hidden one (no group): then this
    // message names it itself.
    std::string name;
    if (opt->get_group().empty()) {
      if (!opt->get_lnames().empty())
        name = "--" + opt->get_lnames().front() + ": ";
      else if (!opt->get_snames().empty())
        name = "-" + opt->get_snames().front() + ": ";
    }
    const CLI::Validator finite(
        [name](std::string& value) -> std::string {
          const char* begin = value.c_str();
          char* end = nullptr;
          errno = 0;
          const double x = std::strtod(begin, &end);
          if (end == begin || *end != '\0' || std::isfinite(x))
            return {};  // not a number, or a finite one
          return name + "expected a finite number, found '" + Printable(value) + "'" +
                 (errno == ERANGE ? " (beyond the largest double)" : "") +
                 " (for a file of that name, write ./" + Printable(value) + ")";
        },
        "", "finite");
    // transform(): placed before the option's own validators, so that their messages (CLI11's
    // range text, which names no option) do not speak first.
    opt->transform(finite);
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    RefuseNonFiniteNumbers(*sub);
}

void PrintError(const std::string& message) {
  std::string out = "imuconv: error: ";
  for (char c : message) {
    out += c;
    if (c == '\n') out += "  ";
  }
  std::cerr << out << "\n";
}

void PrintWarnings(const std::vector<std::string>& warnings) {
  for (const auto& w : warnings) std::cerr << "imuconv: warning: " << w << "\n";
}

nlohmann::json WithWarnings(nlohmann::json out, const std::vector<std::string>& warnings) {
  if (!warnings.empty()) out["warnings"] = warnings;
  return out;
}

int ReportFailure(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e) != nullptr) {
    PrintError("internal error: out of memory (" + std::string(e.what()) + ")");
    return kExitInternal;
  }
  if (dynamic_cast<const std::logic_error*>(&e) != nullptr) {
    PrintError("internal error (a defect of imuconv or of a plugin; please report it): " +
               std::string(e.what()));
    return kExitInternal;
  }
  PrintError(e.what());
  return kExitBadInput;
}

void PrintLabelledMatrix(std::ostream& out, const Mat15& m,
                         const std::vector<std::string>& row_blocks,
                         const std::vector<std::string>& col_blocks) {
  const auto axes = [](const std::vector<std::string>& blocks) {
    std::vector<std::string> labels;
    for (const auto& b : blocks)
      for (const char* ax : {"x", "y", "z"}) labels.push_back(b + "." + ax);
    return labels;
  };
  const auto rl = axes(row_blocks), cl = axes(col_blocks);
  // Every cell is one space and then its text right-aligned in kCellWidth, the widest "%.4g"
  // prints ("-1.234e-100"), so that columns never run together (they did at width 10 with a
  // separator only in the padding: "2.429e-16-1.041e-16") and stay aligned for any value.
  constexpr int kCellWidth = 11;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%-10s", "");
  out << buf;
  for (int c = 0; c < 15; ++c) {
    std::snprintf(buf, sizeof buf, " %*s", kCellWidth, cl[static_cast<std::size_t>(c)].c_str());
    out << buf;
  }
  out << "\n";
  for (int r = 0; r < 15; ++r) {
    if (r % 3 == 0 && r) out << "\n";
    std::snprintf(buf, sizeof buf, "%-10s", rl[static_cast<std::size_t>(r)].c_str());
    out << buf;
    for (int c = 0; c < 15; ++c) {
      const double v = m(r, c);
      if (v == 0.0)
        std::snprintf(buf, sizeof buf, " %*s", kCellWidth, "0");
      else
        std::snprintf(buf, sizeof buf, " %*.4g", kCellWidth, v);
      out << buf;
    }
    out << "\n";
  }
  out.flush();
}

std::string UnknownConventionMessage(const Registry& reg, PluginKind kind, const std::string& id,
                                     const std::vector<LoadIssue>& load_issues) {
  if (reg.has(kind, id)) return "";
  const bool state = kind == PluginKind::StateConvention;
  std::string known;
  for (const auto& k : reg.ids(kind)) known += (known.empty() ? "" : ", ") + k;
  std::string msg = std::string("unknown ") + (state ? "state" : "increment") + " convention " +
                    Quoted(id) + DidYouMean(id, reg.ids(kind)) + "; known: " + known;
  const PluginKind other = state ? PluginKind::IncrementConvention : PluginKind::StateConvention;
  if (reg.has(other, id))
    msg += " (" + Quoted(id) + " is " + (state ? "an increment" : "a state") + " convention)";
  if (!load_issues.empty())
    msg += "\n" + std::to_string(load_issues.size()) +
           " plugin file(s) failed to load; see 'imuconv plugins'";
  return msg;
}

void LoadRegistryWithStateConvention(Registry& reg, const CommandContext& ctx,
                                     const std::string& state_convention) {
  const std::vector<LoadIssue> issues = LoadRegistry(reg, ctx);
  PrintLoadIssues(issues);
  const std::string unknown =
      UnknownConventionMessage(reg, PluginKind::StateConvention, state_convention, issues);
  if (!unknown.empty()) throw Error("--convention: " + unknown);
}

}  // namespace imuconv::cli
