// A std::streambuf over a FILE*, for reading a (temporary) file with a std::istream in blocks.
// Internal to imuconv_pipeline (the result-array collector reads the output's text back with it).
#pragma once

#include <cstdio>
#include <streambuf>
#include <vector>

namespace imuconv::pipeline::detail {

/// A std::streambuf reading a FILE* in blocks (nlohmann's own FILE* adapter calls fgetc once
/// per character).
class FileReader : public std::streambuf {
 public:
  explicit FileReader(std::FILE* f) : file_(f), block_(1 << 16) {}

 protected:
  int_type underflow() override {
    const std::size_t n = std::fread(block_.data(), 1, block_.size(), file_);
    if (n == 0) return traits_type::eof();
    setg(block_.data(), block_.data(), block_.data() + n);
    return traits_type::to_int_type(block_[0]);
  }

 private:
  std::FILE* file_;
  std::vector<char> block_;
};

}  // namespace imuconv::pipeline::detail
