// Streams a text file line by line, counting lines (1-based), in blocks of 64 KiB.
//
// Lines are capped at 1 MiB and a NUL byte is refused, so a binary file fails at once
// instead of filling memory; regular files only (see input_file.h), so a FIFO or a device
// cannot block or never end.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "../io/input_file.h"

namespace imuconv::pipeline::data {

class LineReader {
 public:
  static constexpr std::size_t kMaxLine = 1u << 20;
  static constexpr std::size_t kBlock = 1u << 16;
  explicit LineReader(const std::string& path);
  /// The next line without its "\n" (and "\r"; a UTF-8 BOM is dropped from line 1). False at
  /// the end of the file. Throws ReadError naming the line for a NUL byte or a line > 1 MiB.
  bool next(std::string& line);
  std::size_t line_no() const noexcept { return line_no_; }

 private:
  bool fill();
  std::string path_;
  InputFile in_;
  std::vector<char> buf_;
  std::size_t pos_ = 0, end_ = 0;
  std::size_t line_no_ = 0;
  bool eof_ = false;
};

}  // namespace imuconv::pipeline::data
