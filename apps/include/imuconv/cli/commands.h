// The imuconv command line: each subcommand lives in its own cmd_<name>.cpp and provides one
// Register<Name>Command function, called from main.cpp. To add a subcommand: write
// cmd_<name>.cpp (it is picked up by apps/CMakeLists.txt's glob) and add its row to
// IMUCONV_COMMANDS below. The shape (cmd_convert.cpp, cmd_check.cpp): an options struct, a
// Run<Name>Command(ctx, options) that returns the exit code and needs no CLI11 (declared in
// cmd_<name>.h, so that tests call it), a Declare<Name>Command that only gives the description
// and maps the flags onto the options, and a Register function that adds the two as one
// subcommand (AddCommand). The judging commands end in one tail: judgment.h (print the
// verdict, exit by it) and report_destination.h (--report).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "imuconv/registry.h"

namespace imuconv::cli {

struct CommandContext {
  std::vector<std::string> plugin_dirs_main;  ///< --plugin-dir before the subcommand
  std::vector<std::string> plugin_dirs_sub;   ///< --plugin-dir after it
  bool allow_plugin_override =
      false;          ///< --allow-plugin-override: a duplicate id is a warning, the first wins
  int exit_code = 0;  ///< set by the subcommand that ran
  /// -q before the subcommand: -1, only the results, warnings and errors (no summaries, no
  /// "wrote" lines); -v: 1, also the plugin search path, each plugin loaded and the time taken,
  /// on stderr; 0 otherwise. Warnings and errors are never silenced.
  int verbosity = 0;
  bool quiet() const { return verbosity < 0; }
  bool verbose() const { return verbosity > 0; }

  /// Every --plugin-dir, in the order given (searched before the default path).
  std::vector<std::string> plugin_dirs() const;
};

/// A usage mistake the option parser cannot see, found by a command's own checks (exit 2,
/// reported as CLI11 reports its own).
struct UsageError {
  std::string message;
};

/// Makes run() the subcommand's action: its return value is the exit code, and a UsageError
/// it throws is reported as a usage error.
void SetCommandAction(CLI::App& sub, CommandContext& ctx, std::function<int()> run);

/// The check on every option that names an output file (-o, --report, --tum, --errors): an
/// empty value is refused, naming the option (exit 2), instead of meaning "not given" or
/// standard output: `-o "$OUT"` with OUT unset must not write somewhere the user did not say.
CLI::Validator OutputPathCheck();

/// An option that names an output file, `names` ("-o,--output"), into `path` (a std::string or
/// a std::optional<std::string>): shown as `type_name` in --help and checked by
/// OutputPathCheck. Returns the option, for what else it is (->required()).
template <typename Path>
CLI::Option* AddOutputPathOption(CLI::App& sub, const std::string& names, Path& path,
                                 const std::string& help, const std::string& type_name) {
  return sub.add_option(names, path, help)->type_name(type_name)->check(OutputPathCheck());
}

/// --imu IMU.csv of the commands that read real data (nees, optimize): the EuRoC/ASL IMU CSV.
CLI::Option* AddImuCsvOption(CLI::App& sub, std::string& path);

/// --noise NOISE of the commands that read real data (nees, optimize): the four densities, from
/// any of the files that hold them; with --pipeline, replacing its /noise.
CLI::Option* AddNoiseFileOption(CLI::App& sub, std::string& path);

/// The repeatable --plugin-dir DIR option, into `dirs`: before the subcommand (main.cpp,
/// CommandContext::plugin_dirs_main) and after it (AddPluginDirOption, plugin_dirs_sub) alike.
void AddPluginSearchDirOption(CLI::App& app, std::vector<std::string>& dirs);

/// Adds the repeatable --plugin-dir option and the --allow-plugin-override flag to a subcommand.
void AddPluginDirOption(CLI::App& sub, CommandContext& ctx);

/// Adds the subcommand `name` in the shape of every command that loads plugins: one Options
/// struct, held for the program's run; declare(sub, options) gives its description and its
/// flags, onto the options, in the order --help lists them; then the plugin search options
/// (AddPluginDirOption, last in its --help), and run(ctx, options) as the action
/// (SetCommandAction: its return value is the exit code).
template <typename Options>
void AddCommand(CLI::App& app, CommandContext& ctx, const std::string& name,
                void (*declare)(CLI::App*, Options*),
                int (*run)(const CommandContext&, const Options&)) {
  CLI::App* sub = app.add_subcommand(name);
  const auto options = std::make_shared<Options>();
  declare(sub, options.get());
  AddPluginDirOption(*sub, ctx);
  SetCommandAction(*sub, ctx, [&ctx, options, run] { return run(ctx, *options); });
}

/// Loads the plugin search path (--plugin-dir first, then `extra`, IMUCONV_PLUGIN_PATH and the
/// default directory) and returns what failed to load. Throws Error for a duplicate plugin id
/// unless --allow-plugin-override was given.
[[nodiscard]] std::vector<LoadIssue> LoadRegistry(Registry& reg, const CommandContext& ctx,
                                                  const std::vector<std::string>& extra = {});

/// Prints each plugin file that failed to load as "imuconv: warning: <file>: <message>" on stderr
/// (a command that can do without it goes on).
void PrintLoadIssues(const std::vector<LoadIssue>& issues);

/// With -v: the plugin search path of `dirs` (then IMUCONV_PLUGIN_PATH and the default), on stderr.
void PrintSearchPath(const CommandContext& ctx, const std::vector<std::string>& dirs);

/// Prints "imuconv: error: <message>" to stderr (each line of a multi-line message indented).
void PrintError(const std::string& message);

/// Prints each warning as "imuconv: warning: <text>" on stderr (also with -q: warnings are
/// never silenced).
void PrintWarnings(const std::vector<std::string>& warnings);

/// A command's --json object with its warnings as "warnings" (an array of strings), when there
/// are any; unchanged otherwise, so an output without warnings is what it always was.
[[nodiscard]] nlohmann::json WithWarnings(nlohmann::json out,
                                          const std::vector<std::string>& warnings);

/// Prints a failure that stopped a command and returns its exit code (exit_codes.h): 2 (bad
/// input) for the errors imuconv reports about its input (imuconv::Error and every other
/// std::exception that is not one of the two below), 3 (internal error, said so in the message)
/// for a std::logic_error (a broken invariant of imuconv) and std::bad_alloc.
[[nodiscard]] int ReportFailure(const std::exception& e);

/// Refuses a value that reads as a number that is not finite ("nan", "inf", "-Infinity",
/// "1e999", "0x1p99999") in every option of `app` and of all its subcommands, registered or
/// not yet parsed: CLI11 converts them to double and the range validators let NaN through (every
/// comparison with it is false), so a NaN --duration meant the default and a NaN --check-timeout
/// became a deadline. Called once by main after every command is registered, so that a numeric
/// option added later is covered without anyone remembering to. A file literally named "nan" is
/// given as ./nan.
void RefuseNonFiniteNumbers(CLI::App& app);

/// --shard K/N of imuconv run and imuconv montecarlo: two decimal numbers, 0 <= K < N; returns
/// {K, N}. Throws UsageError quoting the text otherwise.
[[nodiscard]] std::pair<unsigned, unsigned> ParseShardOption(const std::string& text);

/// Prints a 15x15 matrix as a table whose rows and columns are labelled with the axes of the
/// two conventions' blocks ("theta.x", ...), exact zeros as "0", the rest to 4 digits.
void PrintLabelledMatrix(std::ostream& out, const Mat15& m,
                         const std::vector<std::string>& row_blocks,
                         const std::vector<std::string>& col_blocks);

/// "unknown state (or increment) convention 'id'; known: ..." (and that the id is one of the
/// other kind, if so) when `id` is not a convention of `kind`; "" when it is.
[[nodiscard]] std::string UnknownConventionMessage(const Registry& reg, PluginKind kind,
                                                   const std::string& id,
                                                   const std::vector<LoadIssue>& load_issues);

/// Loads the registry as LoadRegistry does, prints its load issues, and throws Error
/// "--convention: <UnknownConventionMessage>" when `state_convention` is not a state convention
/// it holds: the start of the commands that work in a state convention the user names.
void LoadRegistryWithStateConvention(Registry& reg, const CommandContext& ctx,
                                     const std::string& state_convention);

/// Every subcommand, in the order `imuconv --help` lists them: COMMAND(Name) for each, so that
/// Register<Name>Command is declared below and called by main.cpp from this one list. Optimize
/// only with Ceres (IMUCONV_HAVE_OPTIMIZE).
#ifdef IMUCONV_HAVE_OPTIMIZE
#define IMUCONV_OPTIMIZE_COMMAND(COMMAND) COMMAND(Optimize)
#else
#define IMUCONV_OPTIMIZE_COMMAND(COMMAND)
#endif
#define IMUCONV_COMMANDS(COMMAND) \
  COMMAND(Plugins)                \
  COMMAND(Conversion)             \
  COMMAND(Convert)                \
  COMMAND(Run)                    \
  COMMAND(Merge)                  \
  COMMAND(Refcase)                \
  COMMAND(Bench)                  \
  COMMAND(Check)                  \
  COMMAND(Montecarlo)             \
  COMMAND(Nees)                   \
  COMMAND(Experiment)             \
  IMUCONV_OPTIMIZE_COMMAND(COMMAND)

#define IMUCONV_DECLARE_COMMAND(Name) \
  void Register##Name##Command(CLI::App& app, CommandContext& ctx);
IMUCONV_COMMANDS(IMUCONV_DECLARE_COMMAND)
#undef IMUCONV_DECLARE_COMMAND

}  // namespace imuconv::cli
