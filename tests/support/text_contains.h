// Whether a command's output or a message holds a piece of text: the one substring test the
// CLI, pipeline, registry and report tests assert with (each file used to define its own).
#pragma once

#include <cstddef>
#include <string>

namespace imuconv::test {

inline bool Has(const std::string& text, const std::string& piece) {
  return text.find(piece) != std::string::npos;
}

/// How many times `piece` occurs in `text`, without overlaps.
inline std::size_t Count(const std::string& text, const std::string& piece) {
  std::size_t n = 0;
  for (std::size_t p = text.find(piece); p != std::string::npos;
       p = text.find(piece, p + piece.size()))
    ++n;
  return n;
}

}  // namespace imuconv::test
