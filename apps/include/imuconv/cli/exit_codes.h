// The exit codes of every imuconv subcommand: one table, printed under every --help (the
// footer below) and documented once, in docs/exit-codes.md.
//
// 1 is "judged inconsistent" because check, montecarlo and nees already used it so (a script
// asks "did the data pass?"); 2 is bad input because every command already used it for a usage
// error and check, montecarlo, nees and merge for an unusable file; 3, which `imuconv run` used
// for an inconsistent check task until the table was made one, is now an internal error, so
// that "the input is wrong" (2, fix your command or files) is never confused with "imuconv is
// wrong" (3, report it).
#pragma once

namespace imuconv::cli {

enum ExitCode : int {
  kExitOk = 0,            ///< done; a judgment (check, montecarlo, nees, plugins --check) passed
  kExitInconsistent = 1,  ///< done, and judged inconsistent (output written as usual)
  kExitBadInput =
      2,  ///< a usage error or an unusable input (file, JSON, id, flag); nothing written
  kExitInternal =
      3,  ///< a failure that is not the input's: a defect of imuconv or a plugin, out of memory
};

/// The table, as the footer of every --help.
inline constexpr const char* kExitCodeFooter =
    "Exit codes (every command): 0 ok, or consistent; 1 judged inconsistent (check, montecarlo, "
    "run's check tasks, plugins --check); 2 bad input (usage, a missing or malformed file, an "
    "unknown id or "
    "flag; nothing is written); 3 internal error (a defect of imuconv or a plugin, out of memory). "
    "docs/exit-codes.md";

}  // namespace imuconv::cli
