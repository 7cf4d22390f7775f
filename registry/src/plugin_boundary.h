// The host side of the plugin boundary: what the registry checks before it trusts a file,
// a string or a call coming from a plugin.
//
// A plugin is code run in this process; nothing here makes that safe (a plugin can crash or
// hang the host, which only `imuconv plugins --check` contains, in a child process). What can
// be contained is contained: a file that is not an ELF shared object is named as such before
// dlopen sees it, a C++ exception thrown through an entry point becomes an Error naming the
// file, a null or malformed string is refused instead of being copied or echoed.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <string>
#include <string_view>
#include <utility>

#include "imuconv/printable.h"
#include "imuconv/registry.h"

namespace imuconv::detail {

/// Longest plugin id accepted; the built-in ones are at most 23 characters. A bound keeps a
/// runaway (unterminated) id from flooding messages.
constexpr std::size_t kMaxPluginIdLength = 64;

/// "" when `id` is a usable plugin id (non-empty; letters, digits, '_', '-', '.'), else why not.
inline std::string IdProblem(const char* id) {
  if (id == nullptr) return "is a null pointer";
  const std::string_view s(id, strnlen(id, kMaxPluginIdLength + 1));
  if (s.empty()) return "is empty";
  if (s.size() > kMaxPluginIdLength)
    return "is longer than " + std::to_string(kMaxPluginIdLength) + " characters (" + Quoted(s) + "...)";
  for (char c : s) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '-' || c == '.';
    if (!ok) return Quoted(s) + " has a character other than letters, digits, '_', '-' and '.'";
  }
  return {};
}

/// "" when `path` names a regular, non-empty file that starts like an ELF shared object, else
/// what it is instead. Checked before dlopen, whose answer for these cases ("Bad file
/// descriptor" through Boost.DLL, or "file too short") does not say what is wrong; never opens
/// a FIFO or device (stat first, then open non-blocking and fstat again).
inline std::string NotASharedObject(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::string("cannot be examined: ") + std::strerror(errno);
  if (!S_ISREG(st.st_mode)) return S_ISDIR(st.st_mode) ? "is a directory, not a plugin file" : "is not a regular file";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) return std::string("cannot be opened: ") + std::strerror(errno);
  unsigned char h[18] = {};
  ssize_t got = 0;
  const bool regular = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  if (regular) {
    do got = ::read(fd, h, sizeof h);
    while (got < 0 && errno == EINTR);
  }
  const int read_errno = errno;
  ::close(fd);
  if (!regular) return "is not a regular file";
  if (got < 0) return std::string("cannot be read: ") + std::strerror(read_errno);
  if (st.st_size == 0 || got == 0) return "is empty (expected an ELF shared object built with imuconv_add_plugin)";
  if (got < 4 || h[0] != 0x7f || h[1] != 'E' || h[2] != 'L' || h[3] != 'F')
    return "is not an ELF shared object (it does not start with the ELF magic bytes; expected a plugin built with "
           "imuconv_add_plugin)";
  if (got < static_cast<ssize_t>(sizeof h)) return "is a truncated ELF file (" + std::to_string(got) + " bytes)";
  // e_type (offset 16) in the file's byte order (e_ident[5]: 1 little, 2 big endian).
  const unsigned type = h[5] == 2 ? (h[16] << 8 | h[17]) : (h[17] << 8 | h[16]);
  if (type != 3) return "is an ELF file but not a shared object (ELF type " + std::to_string(type) + ")";
  return {};
}

/// The message of an exception thrown by plugin code, or a note that it is not a std::exception.
/// Call only inside a catch block.
inline std::string CurrentExceptionText() {
  try {
    throw;
  } catch (const std::exception& e) {
    const char* what = e.what();  // plugin code: may be null
    return what ? "an exception: " + Quoted(what) : "an exception with a null message";
  } catch (...) {
    return "an exception that is not a std::exception";
  }
}

/// Runs f, a call into plugin code; an exception it lets out becomes an Error naming the file
/// and the entry point. This contains entry points fetched without `noexcept` (the Boost.DLL
/// aliases). The interface methods (id(), labels(), retract(), ...) are declared noexcept: an
/// exception thrown inside one ends in std::terminate in the plugin's own frame before the host
/// regains control, so there the guard only catches what the host itself throws.
template <typename F>
auto CallPlugin(const std::string& path, std::string_view what, F&& f) -> decltype(f()) {
  try {
    return std::forward<F>(f)();
  } catch (...) {
    throw Error("plugin " + Quoted(path) + ": " + std::string(what) + " threw " + CurrentExceptionText());
  }
}

}  // namespace imuconv::detail
