// Errors of the pipeline layer. Every message names the file it is about; configuration
// errors carry the JSON pointer of each problem, reader errors the line number.
#pragma once

#include <string>
#include <vector>

#include "imuconv/registry.h"

namespace imuconv::pipeline {

/// One problem in a JSON document: where (RFC 6901 pointer, "" = the whole document) and what.
struct Issue {
  std::string pointer;
  std::string message;
};

/// A JSON document (pipeline, state, measurement file) that is malformed or inconsistent.
/// what() lists the first kShownIssues issues as "FILE: POINTER: MESSAGE", one per line (file
/// and pointer escaped with Printable), then "... and N more problems in FILE" if there were
/// more: a file with 200 000 unknown keys gets a short message, not 200 000 lines.
class ConfigError : public Error {
 public:
  static constexpr std::size_t kShownIssues = 20;
  /// `total`: how many problems were found, when more than issues.size() were (a Checker
  /// stores a bounded number); 0 or less than issues.size() means issues.size().
  ConfigError(std::string file, std::vector<Issue> issues, std::size_t total = 0);
  const std::string& file() const noexcept { return file_; }
  /// The stored issues (at most Checker::kMaxStored when they come from a Checker).
  const std::vector<Issue>& issues() const noexcept { return issues_; }
  /// Every problem found, stored or not.
  std::size_t total() const noexcept { return total_; }

 private:
  std::string file_;
  std::vector<Issue> issues_;
  std::size_t total_;
};

/// A data file (IMU or ground-truth CSV) that cannot be read; what() is "FILE:LINE: MESSAGE"
/// (line 0 when the problem is not about one line, e.g. a file that cannot be opened; FILE
/// escaped with Printable, file() as given).
class ReadError : public Error {
 public:
  ReadError(std::string file, std::size_t line, const std::string& message);
  const std::string& file() const noexcept { return file_; }
  std::size_t line() const noexcept { return line_; }

 private:
  std::string file_;
  std::size_t line_;
};

}  // namespace imuconv::pipeline
