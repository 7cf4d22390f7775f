#include "destination_path.h"

#include <limits.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>

#include "imuconv/printable.h"
#include "imuconv/registry.h"  // imuconv::Error

namespace imuconv::pipeline::destination {

namespace fs = std::filesystem;

std::string KindOf(mode_t m) {
  if (S_ISREG(m)) return "a regular file";
  if (S_ISDIR(m)) return "a directory";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISFIFO(m)) return "a FIFO";
  if (S_ISSOCK(m)) return "a socket";
  if (S_ISLNK(m)) return "a symbolic link";
  return "a file of unknown kind";
}

/// N when `p` names this process's descriptor N (/dev/fd/N, /proc/self/fd/N,
/// /proc/thread-self/fd/N, /proc/<our pid>/fd/N). Those are written through the descriptor we
/// already hold: reopening them would start at offset 0 without the append mode of `>>`, and
/// following them as links would replace whatever file the shell opened.
std::optional<int> OwnDescriptor(const std::string& p) {
  // By name first: /dev and /proc are not mounted everywhere (some containers).
  if (p == "-" || p == "/dev/stdout") return 1;
  if (p == "/dev/stderr") return 2;
  const fs::path path(p);
  const std::string name = path.filename().string();
  if (name.empty() || name.size() > 9 ||
      !std::all_of(name.begin(), name.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  const std::string parent = path.parent_path().string();
  if (parent.empty()) return std::nullopt;  // a file called "3" in the working directory
  if (parent == "/dev/fd" || parent == "/proc/self/fd" || parent == "/proc/thread-self/fd")
    return std::stoi(name);
  char buf[PATH_MAX];
  if (!::realpath(path.parent_path().c_str(), buf)) return std::nullopt;
  const std::string dir(buf), proc = "/proc/" + std::to_string(::getpid());
  bool ours = dir == proc + "/fd";
  const std::string task = proc + "/task/";
  if (!ours && dir.size() > task.size() + 3 && dir.compare(0, task.size(), task) == 0 &&
      dir.compare(dir.size() - 3, 3, "/fd") == 0) {
    const std::string tid = dir.substr(task.size(), dir.size() - 3 - task.size());
    ours = std::all_of(tid.begin(), tid.end(), [](char c) { return c >= '0' && c <= '9'; });
  }
  if (!ours) return std::nullopt;
  return std::stoi(name);
}

std::string ReadLink(const std::string& p, const std::string& shown) {
  std::string buf(256, '\0');
  for (;;) {
    const ssize_t n = ::readlink(p.c_str(), buf.data(), buf.size());
    if (n < 0)
      throw Error(shown + ": cannot read the symbolic link " + Printable(p) + ": " +
                  std::strerror(errno));
    if (static_cast<std::size_t>(n) < buf.size()) return buf.substr(0, static_cast<std::size_t>(n));
    buf.resize(buf.size() * 2);
  }
}

/// 12 characters of [A-Za-z0-9] (71 bits) for a temporary's name.
std::string RandomSuffix() {
  static const char kChars[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  unsigned char b[12];
  if (::getrandom(b, sizeof b, 0) != static_cast<ssize_t>(sizeof b)) {
    std::random_device rd;
    for (auto& c : b) c = static_cast<unsigned char>(rd());
  }
  std::string s;
  for (unsigned char c : b) s += kChars[c % 62];
  return s;
}

/// The real path of `p` (every link resolved), or nullopt with errno set.
std::optional<std::string> RealPath(const std::string& p) {
  char buf[PATH_MAX];
  if (!::realpath(p.c_str(), buf)) return std::nullopt;
  return std::string(buf);
}

/// `inner` is `outer` or lies below it (both real paths).
bool IsInside(const std::string& inner, const std::string& outer) {
  if (outer == "/") return true;
  return inner == outer ||
         (inner.size() > outer.size() && inner.compare(0, outer.size(), outer) == 0 &&
          inner[outer.size()] == '/');
}

}  // namespace imuconv::pipeline::destination
