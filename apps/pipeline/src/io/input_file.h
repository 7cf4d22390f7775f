// Opening an input for reading: regular files only.
//
// A FIFO, a device or a socket named as an input would block a reader forever (a FIFO with no
// writer), never end (/dev/zero) or have side effects on open (a tape). The path is checked
// with stat() before it is opened, then opened with O_NONBLOCK (so that even a FIFO swapped in
// between the two calls cannot block the open) and checked again with fstat() on the open
// descriptor, which is what is actually read. Every file opened here is recorded as an input
// (imuconv/pipeline/input_registry.h), so that no output of this process can replace it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace imuconv::pipeline::data {

class InputFile {
 public:
  /// Throws ReadError(path, 0, ...) if `path` is missing, unreadable or not a regular file.
  explicit InputFile(const std::string& path);
  ~InputFile();
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  /// Reads up to n bytes; 0 at the end of the file. Throws ReadError on a read error.
  std::size_t read(char* buf, std::size_t n);
  /// The size fstat() reported when the file was opened (0 for files like those in /proc,
  /// whose real length is only known by reading them).
  std::uint64_t size() const noexcept { return size_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

/// The whole content of a regular file of at most `limit` bytes; a larger one is refused with
/// "is larger than <limit_text>" plus `advice` (the size is checked before reading, and the
/// read is capped too, in case the file grows).
std::string ReadWholeFile(const std::string& path, std::size_t limit, const std::string& limit_text,
                          const std::string& advice);

}  // namespace imuconv::pipeline::data
