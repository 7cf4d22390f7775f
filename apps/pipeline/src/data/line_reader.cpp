#include "line_reader.h"

#include <algorithm>
#include <cstring>

#include "imuconv/pipeline/errors.h"

namespace imuconv::pipeline::data {

LineReader::LineReader(const std::string& path) : path_(path), in_(path), buf_(kBlock) {}

bool LineReader::fill() {
  if (eof_) return false;
  pos_ = 0;
  end_ = in_.read(buf_.data(), buf_.size());
  eof_ = end_ == 0;
  return !eof_;
}

bool LineReader::next(std::string& line) {
  line.clear();
  bool any = false;
  while (true) {
    if (pos_ == end_ && !fill()) {
      if (!any) return false;
      break;
    }
    const char* start = buf_.data() + pos_;
    const std::size_t avail = end_ - pos_;
    const auto* nl = static_cast<const char*>(std::memchr(start, '\n', avail));
    const std::size_t len = nl ? static_cast<std::size_t>(nl - start) : avail;
    // What fits under the cap is checked for NUL bytes first (as a byte-wise reader would).
    const std::size_t room = kMaxLine + 1 - line.size();
    const std::size_t take = std::min(len, room);
    if (std::memchr(start, '\0', take) != nullptr)
      throw ReadError(path_, line_no_ + 1, "contains a NUL byte; expected a text (CSV) file");
    if (len > kMaxLine - line.size())
      throw ReadError(path_, line_no_ + 1, "line is longer than 1 MiB; expected a text (CSV) file");
    line.append(start, len);
    any = true;
    pos_ += len;
    if (nl) {
      ++pos_;
      break;
    }
  }
  ++line_no_;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line_no_ == 1 && line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0)
    line.erase(0, 3);  // UTF-8 BOM
  return true;
}

}  // namespace imuconv::pipeline::data
