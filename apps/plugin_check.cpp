// The child-process check behind `imuconv plugins --check DIR`.
//
// A plugin is code in the host process: the registry contains what it can (exceptions through
// the entry points, null and malformed strings), but a segfault, an exception inside a
// noexcept method (std::terminate) or an endless loop cannot be contained in-process. Here
// each file is loaded in a forked child that reports through a pipe; the parent only reads
// the pipe, waits with a deadline, and kills and reaps the child's process group.
//
// A process group is not enough: a plugin can start a process that leaves it (setsid(), or the
// daemon's double fork) and outlives the check, holding the report pipe open. So the checking
// process makes itself a child subreaper (Linux, PR_SET_CHILD_SUBREAPER) while it checks: every
// process the plugin started whose parent dies is re-parented to it instead of to init. Once the
// child has exited, the processes whose parent is this one (found by walking /proc) are
// killed and reaped, generation by generation, and the plugin is reported as having started a
// process that outlived it. During a check this process has no other children.
#include "plugin_check.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <thread>

#include "imuconv/printable.h"
#include "plugin_exercise.h"

namespace imuconv::cli {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// What the child reads back is bounded: a report is one line, stderr is kept for its tail.
constexpr std::size_t kMaxReport = 64 * 1024;
constexpr std::size_t kMaxStderrTail = 4 * 1024;

const char* SignalName(int sig) {
  switch (sig) {
    case SIGSEGV:
      return "SIGSEGV";
    case SIGBUS:
      return "SIGBUS";
    case SIGABRT:
      return "SIGABRT";
    case SIGILL:
      return "SIGILL";
    case SIGFPE:
      return "SIGFPE";
    case SIGKILL:
      return "SIGKILL";
    case SIGTERM:
      return "SIGTERM";
    case SIGINT:
      return "SIGINT";
    case SIGTRAP:
      return "SIGTRAP";
    case SIGSYS:
      return "SIGSYS";
    case SIGPIPE:
      return "SIGPIPE";
    case SIGXCPU:
      return "SIGXCPU";
    case SIGXFSZ:
      return "SIGXFSZ";
    default:
      return nullptr;
  }
}

void WriteAll(int fd, const std::string& s) {
  std::size_t done = 0;
  while (done < s.size()) {
    const ssize_t n = ::write(fd, s.data() + done, s.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

[[noreturn]] void RunChild(const std::string& file, int report_fd, int stderr_fd, pid_t parent) {
  ::setpgid(0, 0);  // its own group, so that the parent can kill whatever it starts
#ifdef __linux__
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // dies with the parent (e.g. Ctrl-C on imuconv)
  ::prctl(PR_SET_DUMPABLE, 0);         // a crash leaves no core file behind
#endif
  if (::getppid() != parent) ::_exit(127);  // the parent died before PDEATHSIG was set
  const rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  // The plugin's own output must not reach the report: stdout and stdin are /dev/null,
  // stderr goes to a pipe the parent keeps the tail of.
  const int devnull = ::open("/dev/null", O_RDWR | O_CLOEXEC);
  if (devnull >= 0) {
    ::dup2(devnull, STDIN_FILENO);
    ::dup2(devnull, STDOUT_FILENO);
  }
  ::dup2(stderr_fd, STDERR_FILENO);
  std::string report;
  try {
    report = "O" + ExercisePlugin(file);
  } catch (const std::exception& e) {
    report = std::string("E") + e.what();
  } catch (...) {
    report = "Efailed with an exception that is not a std::exception";
  }
  WriteAll(report_fd, report);
  ::_exit(0);  // no destructors, no atexit handlers: nothing of the parent's state is flushed twice
}

// Appends n bytes to `into`, keeping at most `cap` bytes of it: its first (a report: what the
// child says first is what matters) or, with keep_tail, its last (stderr: the last lines say why
// it died). What a plugin writes can be anything, of any length.
void AppendBounded(std::string& into, const char* data, std::size_t n, std::size_t cap,
                   bool keep_tail) {
  into.append(data, n);
  if (into.size() > cap) {
    if (keep_tail)
      into.erase(0, into.size() - cap);
    else
      into.resize(cap);
  }
}

// Appends what fd has to `into` (at most `cap` bytes kept: the first for the report, the last
// for stderr). Returns false at end of file or on an error.
bool Drain(int fd, std::string& into, std::size_t cap, bool keep_tail) {
  char buf[4096];
  const ssize_t n = ::read(fd, buf, sizeof buf);
  if (n < 0) return errno == EINTR || errno == EAGAIN;
  if (n == 0) return false;
  AppendBounded(into, buf, static_cast<std::size_t>(n), cap, keep_tail);
  return true;
}

std::string LastLine(const std::string& text) {
  std::size_t end = text.find_last_not_of("\r\n \t");
  if (end == std::string::npos) return {};
  const std::size_t start = text.find_last_of('\n', end);
  std::string line = text.substr(start == std::string::npos ? 0 : start + 1,
                                 end + 1 - (start == std::string::npos ? 0 : start + 1));
  if (line.size() > 200) line = line.substr(0, 200) + "...";
  return line;
}

std::string Seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", s);
  return buf;
}

// Restores SIGCHLD's disposition: an inherited SIG_IGN would make the kernel reap the child
// before waitpid could read its status.
struct DefaultSigchld {
  struct sigaction old {};
  DefaultSigchld() {
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    ::sigaction(SIGCHLD, &dfl, &old);
  }
  ~DefaultSigchld() { ::sigaction(SIGCHLD, &old, nullptr); }
};

// True once the child has exited (it is not reaped: its pid stays ours).
bool HasExited(pid_t pid) {
  siginfo_t si{};
  return ::waitid(P_PID, static_cast<id_t>(pid), &si, WEXITED | WNOHANG | WNOWAIT) == 0 &&
         si.si_pid == pid;
}

// Appends everything fd holds now (it is non-blocking) to `into`, bounded as Drain is.
void DrainAvailable(int fd, std::string& into, std::size_t cap, bool keep_tail) {
  for (int i = 0; i < 1024; ++i) {  // at most 4 MiB: a writer that keeps writing is not waited for
    char buf[4096];
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    AppendBounded(into, buf, static_cast<std::size_t>(n), cap, keep_tail);
  }
}

#ifdef __linux__
// This process as a child subreaper for its lifetime (restored after).
struct Subreaper {
  int before = 0;
  bool set = false;
  Subreaper() {
    if (::prctl(PR_GET_CHILD_SUBREAPER, &before) != 0) before = 0;
    set = ::prctl(PR_SET_CHILD_SUBREAPER, 1) == 0;
  }
  ~Subreaper() {
    if (set && before == 0) ::prctl(PR_SET_CHILD_SUBREAPER, 0);
  }
};

// The processes whose parent is `parent`, from /proc/PID/stat (field 4, after the command name
// in parentheses, which may itself hold spaces and parentheses).
std::vector<pid_t> ChildrenOf(pid_t parent) {
  std::vector<pid_t> kids;
  std::error_code ec;
  for (fs::directory_iterator it("/proc", ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(it->path() / "stat");
    std::string stat;
    if (!std::getline(in, stat)) continue;  // gone meanwhile
    const std::size_t close = stat.rfind(')');
    if (close == std::string::npos) continue;
    char state = 0;
    long ppid = 0;
    if (std::sscanf(stat.c_str() + close + 1, " %c %ld", &state, &ppid) == 2 && ppid == parent)
      kids.push_back(static_cast<pid_t>(std::stol(name)));
  }
  return kids;
}

// Kills and reaps every process re-parented to this one (and, as they die, theirs), the check's
// child being gone already. Returns how many there were; `all` is false if some were still
// appearing after many rounds (a fork bomb).
std::size_t KillOrphans(bool& all) {
  std::size_t killed = 0;
  all = true;
  for (int round = 0; round < 1000; ++round) {
    const std::vector<pid_t> kids = ChildrenOf(::getpid());
    if (kids.empty()) return killed;
    for (pid_t k : kids) ::kill(k, SIGKILL);
    for (pid_t k : kids) {
      while (::waitpid(k, nullptr, 0) < 0 && errno == EINTR) {
      }
      ++killed;
    }
  }
  all = false;
  return killed;
}
#endif

struct Fd {
  int fd = -1;
  ~Fd() { reset(); }
  void reset() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
};

}  // namespace

const char* OutcomeName(PluginCheck::Outcome o) {
  // One name per outcome, in the order of the enum (plugin_check.h).
  static constexpr const char* kNames[] = {"ok",        "refused",   "crashed",
                                           "timed_out", "no_result", "left_processes"};
  static_assert(
      std::size(kNames) == static_cast<std::size_t>(PluginCheck::Outcome::LeftProcesses) + 1,
      "a name for every PluginCheck::Outcome");
  const auto i = static_cast<std::size_t>(o);
  return i < std::size(kNames) ? kNames[i] : "no_result";
}

std::string SafeText(const std::string& text) {
  const std::string escaped = Printable(text);
  std::string doubled;  // what Printable makes of text that needs no escape: backslashes doubled
  doubled.reserve(text.size());
  for (char c : text) doubled += c == '\\' ? std::string("\\\\") : std::string(1, c);
  return escaped == doubled ? text : escaped;
}

std::vector<std::string> PluginFilesIn(const std::string& dir) {
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (st.type() == fs::file_type::not_found)
    throw Error("plugin directory " + Quoted(dir) + " does not exist");
  if (ec) throw Error("cannot access plugin directory " + Quoted(dir) + ": " + ec.message());
  if (!fs::is_directory(st)) throw Error(Quoted(dir) + " is not a directory");
  fs::directory_iterator it(dir, ec);
  if (ec) throw Error("cannot list plugin directory " + Quoted(dir) + ": " + ec.message());
  std::vector<std::string> files;
  for (const fs::directory_iterator end{}; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() > 3 && name.rfind("imuconv_plugin_", 0) == 0 &&
        name.compare(name.size() - 3, 3, ".so") == 0)
      files.push_back(it->path().string());
  }
  if (ec) throw Error("listing plugin directory " + Quoted(dir) + " failed: " + ec.message());
  std::sort(files.begin(), files.end());
  return files;
}

PluginCheck CheckPluginInChild(const std::string& file, double timeout_s) {
  PluginCheck result;
  result.file = file;
  DefaultSigchld sigchld;
#ifdef __linux__
  const Subreaper subreaper;  // before the fork: whatever the plugin starts comes back to us
#endif
  int report_pipe[2], stderr_pipe[2];
  if (::pipe2(report_pipe, O_CLOEXEC) != 0)
    throw Error(std::string("cannot create a pipe: ") + std::strerror(errno));
  Fd report_r{report_pipe[0]}, report_w{report_pipe[1]};
  if (::pipe2(stderr_pipe, O_CLOEXEC) != 0)
    throw Error(std::string("cannot create a pipe: ") + std::strerror(errno));
  Fd stderr_r{stderr_pipe[0]}, stderr_w{stderr_pipe[1]};

  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);  // nothing buffered is inherited and written twice
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0)
    throw Error("cannot start a child process to check " + Quoted(file) + ": " +
                std::strerror(errno));
  if (pid == 0) {
    ::close(report_pipe[0]);
    ::close(stderr_pipe[0]);
    RunChild(file, report_pipe[1], stderr_pipe[1], parent);
  }
  ::setpgid(pid, pid);  // also done by the child; whichever runs first
  report_w.reset();
  stderr_w.reset();
  // Non-blocking reads: a process the plugin started may hold the pipes open after the child
  // has exited, and its report is complete then.
  for (int fd : {report_r.fd, stderr_r.fd}) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);

  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(timeout_s));
  auto remaining_ms = [&] {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    return left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, 1000));
  };
  std::string report, err;
  bool timed_out = false;
  // 1. Read both pipes until the child closes them or exits, or the deadline passes.
  while (report_r.fd >= 0 || stderr_r.fd >= 0) {
    if (Clock::now() >= deadline) {
      timed_out = true;
      break;
    }
    if (HasExited(
            pid)) {  // what it wrote is in the pipes; whoever else holds them is not waited for
      for (Fd* f : {&report_r, &stderr_r})
        if (f->fd >= 0)
          DrainAvailable(f->fd, f == &report_r ? report : err,
                         f == &report_r ? kMaxReport : kMaxStderrTail, f != &report_r);
      break;
    }
    pollfd fds[2];
    nfds_t n = 0;
    Fd* owners[2];
    for (Fd* f : {&report_r, &stderr_r})
      if (f->fd >= 0) {
        fds[n] = {f->fd, POLLIN, 0};
        owners[n++] = f;
      }
    const int r =
        ::poll(fds, n, std::min(remaining_ms(), 20));  // 20 ms: the child's exit is seen soon
    if (r < 0 && errno != EINTR) break;
    for (nfds_t i = 0; r > 0 && i < n; ++i) {
      if (!(fds[i].revents & (POLLIN | POLLHUP | POLLERR | POLLNVAL))) continue;
      const bool is_report = owners[i] == &report_r;
      if (!Drain(fds[i].fd, is_report ? report : err, is_report ? kMaxReport : kMaxStderrTail,
                 !is_report))
        owners[i]->reset();
    }
  }
  // 2. The pipes are closed; the child may still be on its way out (or have closed them and
  //    gone on running): wait for its exit, without reaping it yet, until the deadline.
  while (!timed_out) {
    siginfo_t si{};
    const int w = ::waitid(P_PID, static_cast<id_t>(pid), &si, WEXITED | WNOHANG | WNOWAIT);
    if (w == 0 && si.si_pid == pid) break;
    if (w < 0 && errno != EINTR) break;
    if (Clock::now() >= deadline) {
      timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  // 3. Kill the group (the child if it still runs, and anything it started) while the
  //    unreaped child still holds its pid, so the number cannot name another process; reap.
  ::kill(-pid, SIGKILL);
  ::kill(pid, SIGKILL);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  // 4. What it started that outlived it: re-parented to us, killed and reaped.
  std::size_t outlived = 0;
  bool all_killed = true;
#ifdef __linux__
  outlived = KillOrphans(all_killed);
#endif

  const std::string last_err = LastLine(err);
  const std::string stderr_note =
      last_err.empty() ? "" : "; last line on stderr: " + Quoted(last_err);
  if (timed_out) {
    result.outcome = PluginCheck::Outcome::TimedOut;
    result.message = "did not finish within " + Seconds(timeout_s) + " s (killed)";
  } else if (!report.empty() && report[0] == 'O') {
    result.outcome = PluginCheck::Outcome::Ok;
    result.message = "ok (" + SafeText(report.substr(1)) + ")";
  } else if (!report.empty() && report[0] == 'E') {
    result.outcome = PluginCheck::Outcome::Refused;
    result.message = SafeText(report.substr(1));
  } else if (WIFSIGNALED(status)) {
    result.outcome = PluginCheck::Outcome::Crashed;
    const int sig = WTERMSIG(status);
    const char* name = SignalName(sig);
    result.message = "crashed with signal " + (name ? std::string(name) : std::to_string(sig));
    if (sig == SIGABRT)
      result.message += " (abort or std::terminate, e.g. an exception thrown in a noexcept method)";
    result.message += stderr_note;
  } else {
    result.outcome = PluginCheck::Outcome::NoResult;
    result.message = "stopped without a result (exit status " +
                     std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")" +
                     stderr_note;
  }
  if (outlived > 0) {
    const std::string what =
        "started " + std::to_string(outlived) + " process(es) that outlived it (" +
        (all_killed ? "killed" : "still starting more after 1000 rounds of killing them") + ")";
    if (result.outcome == PluginCheck::Outcome::TimedOut) {
      result.message += "; it also " + what;
    } else {
      result.message = what + "; the load itself: " + result.message;
      result.outcome = PluginCheck::Outcome::LeftProcesses;
    }
  }
  return result;
}

}  // namespace imuconv::cli
