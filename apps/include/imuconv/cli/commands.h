// The imuconv command line: each subcommand lives in its own cmd_<name>.cpp and provides one
// Register<Name>Command function, called from main.cpp. To add a subcommand: write
// cmd_<name>.cpp (it is picked up by apps/CMakeLists.txt's glob), declare its Register
// function below and add it to the list in main.cpp. The shape (cmd_convert.cpp,
// cmd_check.cpp): an options struct, a Run<Name>Command(ctx, options) that returns the exit
// code and needs no CLI11 (declared in cmd_<name>.h, so that tests call it), and a Register
// function that only maps the flags onto the options (SetCommandAction). The judging commands
// end in one tail: judgment.h (print the verdict, exit by it) and report_destination.h
// (--report).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
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

/// The repeatable --plugin-dir DIR option, into `dirs`: before the subcommand (main.cpp,
/// CommandContext::plugin_dirs_main) and after it (AddPluginDirOption, plugin_dirs_sub) alike.
void AddPluginSearchDirOption(CLI::App& app, std::vector<std::string>& dirs);

/// Adds the repeatable --plugin-dir option and the --allow-plugin-override flag to a subcommand.
void AddPluginDirOption(CLI::App& sub, CommandContext& ctx);

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

void RegisterPluginsCommand(CLI::App& app, CommandContext& ctx);
void RegisterConversionCommand(CLI::App& app, CommandContext& ctx);
void RegisterConvertCommand(CLI::App& app, CommandContext& ctx);
void RegisterRunCommand(CLI::App& app, CommandContext& ctx);
void RegisterMergeCommand(CLI::App& app, CommandContext& ctx);
void RegisterRefcaseCommand(CLI::App& app, CommandContext& ctx);
void RegisterBenchCommand(CLI::App& app, CommandContext& ctx);
void RegisterCheckCommand(CLI::App& app, CommandContext& ctx);
void RegisterMontecarloCommand(CLI::App& app, CommandContext& ctx);
void RegisterNeesCommand(CLI::App& app, CommandContext& ctx);
void RegisterExperimentCommand(CLI::App& app, CommandContext& ctx);
/// Only with Ceres (IMUCONV_HAVE_OPTIMIZE).
void RegisterOptimizeCommand(CLI::App& app, CommandContext& ctx);

}  // namespace imuconv::cli
