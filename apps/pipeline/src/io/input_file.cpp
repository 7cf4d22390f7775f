#include "input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/input_registry.h"
#include "imuconv/pipeline/standard_descriptors.h"

namespace imuconv::pipeline::data {
namespace {

// What a non-regular file is, for "is a FIFO, not a regular file".
std::string InputKindOf(mode_t m) {
  if (S_ISFIFO(m)) return "is a FIFO, not a regular file";
  if (S_ISCHR(m)) return "is a character device, not a regular file";
  if (S_ISBLK(m)) return "is a block device, not a regular file";
  if (S_ISSOCK(m)) return "is a socket, not a regular file";
  return "is not a regular file";
}

[[noreturn]] void CannotOpen(const std::string& path, int err) {
  // A missing file is the common case and says enough on its own.
  if (err == ENOENT) throw ReadError(path, 0, "cannot open the file for reading");
  throw ReadError(path, 0,
                  std::string("cannot open the file for reading (") + std::strerror(err) + ")");
}

void CheckRegular(const std::string& path, const struct stat& st) {
  if (S_ISDIR(st.st_mode)) throw ReadError(path, 0, "is a directory, not a file");
  if (!S_ISREG(st.st_mode)) throw ReadError(path, 0, InputKindOf(st.st_mode));
}

}  // namespace

InputFile::InputFile(const std::string& path) : path_(path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) CannotOpen(path, errno);
  CheckRegular(path, st);
  fd_ =
      AboveStandardDescriptors(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC));
  if (fd_ < 0) CannotOpen(path, errno);
  try {
    if (::fstat(fd_, &st) != 0) CannotOpen(path, errno);
    CheckRegular(path, st);
  } catch (...) {
    ::close(fd_);
    throw;
  }
  size_ = static_cast<std::uint64_t>(st.st_size);
  // Every file read is an input, which no output may replace (input_registry.h): recorded by the
  // identity of what was opened, whatever name or link led to it.
  RegisterInputDescriptor(fd_, path);
  // Back to blocking reads: O_NONBLOCK only had to protect the open itself.
  const int flags = ::fcntl(fd_, F_GETFL);
  if (flags >= 0) ::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK);
}

InputFile::~InputFile() {
  if (fd_ >= 0) ::close(fd_);
}

std::size_t InputFile::read(char* buf, std::size_t n) {
  while (true) {
    const ssize_t r = ::read(fd_, buf, n);
    if (r >= 0) return static_cast<std::size_t>(r);
    if (errno == EINTR) continue;
    throw ReadError(path_, 0, std::string("cannot read the file (") + std::strerror(errno) + ")");
  }
}

std::string ReadWholeFile(const std::string& path, std::size_t limit, const std::string& limit_text,
                          const std::string& advice) {
  InputFile in(path);
  const std::string too_large = "is larger than " + limit_text + advice;
  if (in.size() > limit) throw ReadError(path, 0, too_large);
  std::string text;
  text.resize(static_cast<std::size_t>(in.size()) + 1);  // +1: notices a file that grew
  std::size_t used = 0;
  while (true) {
    if (used == text.size()) {
      if (used > limit) throw ReadError(path, 0, too_large);
      text.resize(std::min<std::size_t>(limit + 1, std::max<std::size_t>(2 * used, 1u << 16)));
    }
    const std::size_t got = in.read(text.data() + used, text.size() - used);
    if (got == 0) break;
    used += got;
  }
  if (used > limit) throw ReadError(path, 0, too_large);
  text.resize(used);
  return text;
}

}  // namespace imuconv::pipeline::data
