// Whether a command's output or a message holds a piece of text: the one substring test the
// CLI, pipeline, registry and report tests assert with (each file used to define its own).
#pragma once

#include <string>

namespace imuconv::test {

inline bool Has(const std::string& text, const std::string& piece) {
  return text.find(piece) != std::string::npos;
}

}  // namespace imuconv::test
