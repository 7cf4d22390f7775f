// The processes (by pid, from /proc) whose command line holds a marker: how the tests of
// plugins --check and of a pipeline's plugin check see that no child, or what a child forked,
// outlived the command (each child runs imuconv's command line, which names the directory
// checked, so a temporary directory's path marks the test's own processes alone).
#pragma once

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "text_contains.h"

namespace imuconv::test {

inline std::vector<std::string> ProcessesMentioning(const std::string& marker) {
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/proc", ec)) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    if (Has(ReadText(e.path().string() + "/cmdline"), marker)) found.push_back(name);
  }
  return found;
}

}  // namespace imuconv::test
