// Shared by the registry loading tests: the message load_file gives for a file ("" if it loads).
#pragma once

#include <string>

#include "imuconv/registry.h"

namespace imuconv::test {

inline std::string LoadErrorOf(Registry& r, const std::string& path) {
  try {
    r.load_file(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

/// A plugin the test fixtures build (tests/fixtures/CMakeLists.txt), by its path there.
inline std::string FixturePlugin(const std::string& rel) {
  return std::string(IMUCONV_BINARY_DIR) + "/tests/fixtures/" + rel;
}

/// A file in the built-in plugin directory.
inline std::string BuiltInPlugin(const std::string& name) {
  return Registry::default_plugin_dir() + "/" + name;
}

}  // namespace imuconv::test
