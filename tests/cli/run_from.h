// Running the built imuconv as a user types it in a shell: from a chosen working directory (so
// that "out.json" and "./out.json" are relative names, as the user's are), with standard output
// sent where the test says (a file, /dev/full), and under timeout(1), so that a command that
// hangs ends with exit code 124 and fails its test instead of stopping the suite.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <string>

#include "../pipeline/pipeline_test_util.h"

namespace imuconv::test {

/// timeout(1)'s exit code when it had to stop the command.
constexpr int kTimedOut = 124;

/// Runs `imuconv ARGS` (already shell-quoted where needed) from directory `dir`, its standard
/// output into `stdout_to` when given (then CommandResult::out is empty), else captured. The
/// guard is no measurement: any command these tests run ends in seconds, also under ASan on a
/// loaded machine; only a hang reaches 120 s.
inline CommandResult RunImuconvFrom(const std::string& dir, const std::string& args,
                                    const TempDir& tmp, const std::string& stdout_to = "") {
  const std::string out = tmp.file(".stdout"), err = tmp.file(".stderr");
  const std::string cmd = "cd " + ShellQuote(dir) + " && timeout 120 env -u IMUCONV_PLUGIN_PATH " +
                          ShellQuote(Binary()) + " " + args + " > " +
                          ShellQuote(stdout_to.empty() ? out : stdout_to) + " 2> " +
                          ShellQuote(err);
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (stdout_to.empty()) r.out = ReadText(out);
  r.err = ReadText(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

}  // namespace imuconv::test
