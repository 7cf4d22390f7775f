// The host side of the plugin boundary: what the registry checks before it trusts a file,
// a string or a call coming from a plugin.
//
// A plugin is code run in this process; nothing here makes that safe (a plugin can crash or
// hang the host, which only `imuconv plugins --check` contains, in a child process). What can
// be contained is contained: a file that is not an ELF shared object is named as such before
// dlopen sees it, a C++ exception thrown through an entry point becomes an Error naming the
// file, a null or malformed string is refused instead of being copied or echoed.
#pragma once

#include <elf.h>
#include <fcntl.h>
#include <link.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <exception>
#include <string>
#include <string_view>
#include <utility>

#include "imuconv/printable.h"
#include "imuconv/registry.h"
#include "imuconv/utf8.h"

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
    return "is longer than " + std::to_string(kMaxPluginIdLength) + " characters (" + Quoted(s) +
           "...)";
  for (char c : s) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) return Quoted(s) + " has a character other than letters, digits, '_', '-' and '.'";
  }
  return {};
}

/// Longest version or summary string a plugin's descriptor may hold (read with strnlen: a
/// string without its terminating NUL is not read past this).
inline constexpr std::size_t kMaxPluginTextLength = 4096;

/// Why a descriptor's version or summary string cannot be taken (empty if it can): a null
/// pointer, no end within kMaxPluginTextLength bytes, or bytes that are not UTF-8 (they would
/// be copied into imuconv's JSON outputs, "plugins", which then would not be JSON).
inline std::string TextProblem(const char* text) {
  if (text == nullptr) return "is a null pointer";
  const std::string_view s(text, strnlen(text, kMaxPluginTextLength + 1));
  if (s.size() > kMaxPluginTextLength)
    return "is longer than " + std::to_string(kMaxPluginTextLength) + " bytes (" +
           Quoted(s.substr(0, 40)) + "...)";
  if (const std::size_t bad = FirstInvalidUtf8(s); bad != std::string_view::npos)
    return Quoted(s) + " is not UTF-8 (byte " + std::to_string(bad) + ")";
  return {};
}

/// The ELF class, byte order and machine this program was built for (e_ident[4], e_ident[5],
/// e_machine), and the machine's name; machine 0 where the build's architecture is not one
/// named here, which leaves the machine to dlopen.
struct HostElf {
  unsigned char elf_class = sizeof(void*) == 8 ? ELFCLASS64 : ELFCLASS32;
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
  unsigned char byte_order = ELFDATA2MSB;
#else
  unsigned char byte_order = ELFDATA2LSB;
#endif
  unsigned machine =
#if defined(__x86_64__)
      EM_X86_64;
#elif defined(__aarch64__)
      EM_AARCH64;
#elif defined(__i386__)
      EM_386;
#elif defined(__arm__)
      EM_ARM;
#elif defined(__riscv)
      EM_RISCV;
#elif defined(__powerpc64__)
      EM_PPC64;
#else
      0;
#endif
};

/// A readable name of an ELF machine number (e_machine), for messages.
inline std::string ElfMachineName(unsigned machine) {
  static constexpr std::pair<unsigned, const char*> kNames[] = {
      {EM_386, "x86 (32-bit)"}, {EM_PPC64, "PowerPC 64"}, {EM_ARM, "ARM (32-bit)"},
      {EM_X86_64, "x86-64"},    {EM_AARCH64, "aarch64"},  {EM_RISCV, "RISC-V"}};
  for (const auto& [number, name] : kNames)
    if (number == machine) return name;
  return "ELF machine " + std::to_string(machine);
}

/// "" when every segment dlopen maps (PT_LOAD) and the section header table lie within the
/// file's `size` bytes, else what is cut off. The file's class, byte order and machine are the
/// host's (checked before), so its headers read as this program's own ElfW types. dlopen maps a
/// segment whether or not the file holds all of it, and the first touch of a missing page is a
/// SIGBUS: a plugin truncated by an interrupted copy would crash the program instead of being
/// named.
inline std::string TruncatedElf(int fd, off_t size) {
  const auto read_at = [fd](void* to, std::size_t n, off_t at) {
    ssize_t got;
    do got = ::pread(fd, to, n, at);
    while (got < 0 && errno == EINTR);
    return got == static_cast<ssize_t>(n);
  };
  const auto cut = [size](std::uint64_t needed) {
    return "is a truncated ELF shared object (" + std::to_string(size) +
           " bytes; its headers say " + std::to_string(needed) +
           "): an interrupted copy? Copy or rebuild the plugin again";
  };
  ElfW(Ehdr) eh{};
  if (!read_at(&eh, sizeof eh, 0)) return cut(sizeof eh);
  const auto ends_within = [size](std::uint64_t offset, std::uint64_t count, std::uint64_t each) {
    const auto bytes = static_cast<unsigned __int128>(count) * each + offset;
    return bytes <= static_cast<unsigned __int128>(size);
  };
  if (eh.e_phentsize != sizeof(ElfW(Phdr)) || eh.e_phnum == 0)
    return "is an ELF shared object without usable program headers";
  if (!ends_within(eh.e_phoff, eh.e_phnum, eh.e_phentsize))
    return cut(eh.e_phoff + std::uint64_t{eh.e_phnum} * eh.e_phentsize);
  for (unsigned k = 0; k < eh.e_phnum; ++k) {
    ElfW(Phdr) ph{};
    if (!read_at(&ph, sizeof ph, static_cast<off_t>(eh.e_phoff + k * sizeof ph)))
      return cut(eh.e_phoff + (k + 1) * sizeof ph);
    if (ph.p_type == PT_LOAD && !ends_within(ph.p_offset, 1, ph.p_filesz))
      return cut(ph.p_offset + ph.p_filesz);
  }
  // The section headers come last in a linked object: where they are cut, so is the file.
  if (eh.e_shoff != 0 && !ends_within(eh.e_shoff, eh.e_shnum, eh.e_shentsize))
    return cut(eh.e_shoff + std::uint64_t{eh.e_shnum} * eh.e_shentsize);
  return {};
}

/// "" when `path` names a regular, non-empty file that starts like an ELF shared object built
/// for this program's class, byte order and machine, else what it is instead. Checked before
/// dlopen, whose answer for these cases ("Bad file descriptor" through Boost.DLL, "file too
/// short", "wrong ELF class") does not say what is wrong; a plugin cross-built for another
/// machine (build-aarch64's, say) is named for what it is, and a truncated one too (TruncatedElf).
/// Never opens a FIFO or device (stat first, then open non-blocking and fstat again).
inline std::string NotASharedObject(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return std::string("cannot be examined: ") + std::strerror(errno);
  if (!S_ISREG(st.st_mode))
    return S_ISDIR(st.st_mode) ? "is a directory, not a plugin file" : "is not a regular file";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) return std::string("cannot be opened: ") + std::strerror(errno);
  unsigned char h[20] = {};  // e_ident, e_type, e_machine
  ssize_t got = 0;
  const bool regular = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  if (regular) {
    do got = ::read(fd, h, sizeof h);
    while (got < 0 && errno == EINTR);
  }
  const int read_errno = errno;
  struct CloseOnReturn {
    int fd;
    ~CloseOnReturn() { ::close(fd); }
  } close_on_return{fd};
  if (!regular) return "is not a regular file";
  if (got < 0) return std::string("cannot be read: ") + std::strerror(read_errno);
  if (st.st_size == 0 || got == 0)
    return "is empty (expected an ELF shared object built with imuconv_add_plugin)";
  if (got < 4 || h[0] != 0x7f || h[1] != 'E' || h[2] != 'L' || h[3] != 'F')
    return "is not an ELF shared object (it does not start with the ELF magic bytes; expected a "
           "plugin built with "
           "imuconv_add_plugin)";
  if (got < static_cast<ssize_t>(sizeof h))
    return "is a truncated ELF file (" + std::to_string(got) + " bytes)";
  // A 16-bit field in the file's byte order (e_ident[EI_DATA]): e_type at 16, e_machine at 18.
  const auto half = [&h](int at) {
    return h[EI_DATA] == ELFDATA2MSB ? unsigned(h[at] << 8 | h[at + 1])
                                     : unsigned(h[at + 1] << 8 | h[at]);
  };
  const unsigned type = half(16);
  if (type != ET_DYN)
    return "is an ELF file but not a shared object (ELF type " + std::to_string(type) + ")";
  const HostElf host;
  const auto bits = [](unsigned char elf_class) {
    return elf_class == ELFCLASS32   ? "32-bit"
           : elf_class == ELFCLASS64 ? "64-bit"
                                     : "unknown-class";
  };
  if (h[EI_CLASS] != host.elf_class)
    return std::string("is a ") + bits(h[EI_CLASS]) + " ELF shared object; this program is " +
           bits(host.elf_class) + " (rebuild the plugin for this machine)";
  if (h[EI_DATA] != host.byte_order)
    return std::string("is an ELF shared object of the other byte order (") +
           (h[EI_DATA] == ELFDATA2MSB ? "big" : "little") +
           " endian; rebuild the plugin for this machine)";
  const unsigned machine = half(18);
  if (host.machine != 0 && machine != host.machine)
    return "is an ELF shared object for " + ElfMachineName(machine) + "; this program runs on " +
           ElfMachineName(host.machine) + " (rebuild the plugin for this machine)";
  return TruncatedElf(fd, st.st_size);
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
    throw Error("plugin " + Quoted(path) + ": " + std::string(what) + " threw " +
                CurrentExceptionText());
  }
}

}  // namespace imuconv::detail
