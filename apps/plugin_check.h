// imuconv plugins --check: each plugin file loaded and exercised in a child process, so that
// a plugin that crashes or hangs is named instead of taking the command down with it.
#pragma once

#include <string>
#include <vector>

namespace imuconv::cli {

struct PluginCheck {
  /// OutcomeName names them by position: a new outcome goes last, and OutcomeName's
  /// static_assert then counts up to it.
  enum class Outcome { Ok, Refused, Crashed, TimedOut, NoResult, LeftProcesses };
  std::string file;
  Outcome outcome = Outcome::NoResult;
  /// One line, already escaped: "ok (propagator 'rk4' 1.1.0; ...)", the load error, "crashed
  /// with signal SIGSEGV", "did not finish within 20 s (killed)", ...
  std::string message;
};

/// "ok", "refused", "crashed", "timed_out", "no_result", "left_processes": --json's "result".
const char* OutcomeName(PluginCheck::Outcome o);

/// Every imuconv_plugin_*.so in dir, sorted. Throws Error if dir cannot be listed.
std::vector<std::string> PluginFilesIn(const std::string& dir);

/// Forks a child that loads `file` into a fresh registry (ABI handshake, create, id and
/// string checks, a convention's chart and Jacobian checks) and runs a propagator or
/// preintegrator once on a 10 ms synthetic window, then reports through a pipe. The child is
/// killed (with its process group) after timeout_s seconds; it never outlives this call and is
/// always reaped. A process the plugin started that outlives the child (setsid(), a double fork)
/// is found (this process is a child subreaper during the call, Linux), killed and reaped, and
/// the file reported as LeftProcesses. This process never loads the plugin itself.
PluginCheck CheckPluginInChild(const std::string& file, double timeout_s);

/// `text` as it is when it holds no control byte or invalid UTF-8, else Printable(text): for
/// messages already built with Quoted() that come from a child process or a plugin.
std::string SafeText(const std::string& text);

}  // namespace imuconv::cli
