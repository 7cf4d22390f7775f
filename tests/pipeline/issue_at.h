// The message a pipeline's checker gave at one JSON pointer, and EXPECT_ISSUE, which asserts
// that it holds a text: the pipeline tests' way of asserting where an error was found and what
// it says. When no issue stands at the pointer the "message" lists the issues there were, so a
// failure shows what the checker said instead.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/pipeline.h"

namespace imuconv::test {

inline std::string IssueAt(const std::vector<pipeline::Issue>& issues, const std::string& pointer) {
  std::string all;
  for (const auto& i : issues) {
    if (i.pointer == pointer) return i.message;
    all += "\n  " + i.pointer + ": " + i.message;
  }
  return "(no issue at " + pointer + "; issues:" + all + ")";
}

/// The file name the pipeline tests read a document from memory as: the file its messages name.
inline constexpr const char* kMemPipelineFile = "mem/pipeline.json";

/// The issues of reading `doc` as the pipeline file kMemPipelineFile whose relative paths are
/// the repository's (empty if it is read): the checks made before any task runs.
inline std::vector<pipeline::Issue> ReadingIssues(const nlohmann::json& doc) {
  try {
    pipeline::Pipeline::FromJson(doc, kMemPipelineFile, IMUCONV_SOURCE_DIR);
  } catch (const pipeline::ConfigError& e) {
    return e.issues();
  }
  return {};
}

}  // namespace imuconv::test

#define EXPECT_ISSUE(issues, pointer, text)                                          \
  EXPECT_NE(::imuconv::test::IssueAt(issues, pointer).find(text), std::string::npos) \
      << ::imuconv::test::IssueAt(issues, pointer)
