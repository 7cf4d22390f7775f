// Did-you-mean on the command line: when the option parser fails, the word it could not place
// (a mistyped subcommand, an unknown flag) is named with the nearest known ones. CLI11 alone
// says "A subcommand is required" for `imuconv chek` and "not expected: --trails" for a typo.
#include "usage_hint.h"

#include <cstdlib>
#include <string_view>

#include "imuconv/did_you_mean.h"
#include "imuconv/printable.h"

namespace imuconv::cli {

namespace {

// The long and short names of an app's options ("--trials", "-o"); with `visible_only`, not
// those of hidden options (accepted, never suggested).
std::vector<std::string> OptionNames(const CLI::App& app, bool visible_only = false) {
  std::vector<std::string> names;
  for (const CLI::Option* o : app.get_options()) {
    if (visible_only && o->get_group().empty()) continue;
    for (const auto& l : o->get_lnames()) names.push_back("--" + l);
    for (const auto& s : o->get_snames()) names.push_back("-" + s);
  }
  return names;
}

bool Contains(const std::vector<std::string>& v, std::string_view s) {
  for (const auto& x : v)
    if (x == s) return true;
  return false;
}

// An option's value that happens to start with '-' (a negative number) is not a flag.
bool IsNumber(const std::string& s) {
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0';
}

// The options of the main app that take a value (the next argument, unless written NAME=VALUE);
// a flag expects no item (CLI11 gives flags a type size of 1 but zero expected items).
bool TakesValue(const CLI::App& app, std::string_view name) {
  for (const CLI::Option* o : app.get_options())
    if (o->get_items_expected_max() > 0 &&
        (o->check_lname(std::string(name.substr(name.find_first_not_of('-')))) ||
         (name.size() == 2 && o->check_sname(std::string(name.substr(1))))))
      return true;
  return false;
}

}  // namespace

std::string UsageHint(CLI::App& app, int argc, const char* const* argv) {
  std::vector<std::string> subcommands;
  for (const CLI::App* s : app.get_subcommands([](CLI::App*) { return true; }))
    subcommands.push_back(s->get_name());
  const std::vector<std::string> main_options = OptionNames(app);
  // Up to the subcommand: the main app's options and their values.
  int i = 1;
  CLI::App* sub = nullptr;
  for (; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--") break;
    if (a.size() > 1 && a[0] == '-') {
      const std::string name = a.substr(0, a.find('='));
      if (!Contains(main_options, name))
        return "unknown option " + Quoted(name) + DidYouMean(name, OptionNames(app, true)) +
               " before the subcommand";
      if (a.find('=') == std::string::npos && TakesValue(app, name)) ++i;
      continue;
    }
    if (!Contains(subcommands, a)) {
      std::string known;
      for (const auto& s : subcommands) known += (known.empty() ? "" : ", ") + s;
      return "unknown subcommand " + Quoted(a) + DidYouMean(a, subcommands) +
             "; the subcommands are: " + known;
    }
    sub = app.get_subcommand(a);
    ++i;
    break;
  }
  // After it: every word that looks like a flag must be one of the subcommand's (or the main
  // app's, which CLI11 also accepts there). A subcommand that passes unknown flags on (bench)
  // is left to the parser.
  if (sub == nullptr || sub->get_allow_extras()) return "";
  std::vector<std::string> known = OptionNames(*sub), suggested = OptionNames(*sub, true);
  for (const auto& n : main_options) known.push_back(n);
  for (const auto& n : OptionNames(app, true)) suggested.push_back(n);
  for (; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--") break;
    if (a.size() < 2 || a[0] != '-' || IsNumber(a)) continue;
    const std::string name = a.substr(0, a.find('='));
    if (name.rfind("--", 0) != 0 && name.size() > 2) continue;  // -abc: a cluster of short flags
    if (!Contains(known, name))
      return "unknown option " + Quoted(name) + " for 'imuconv " + sub->get_name() + "'" +
             DidYouMean(name, suggested) + "; see 'imuconv " + sub->get_name() + " --help'";
  }
  return "";
}

}  // namespace imuconv::cli
