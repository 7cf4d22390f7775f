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
/// what() lists every issue as "FILE: POINTER: MESSAGE", one per line.
class ConfigError : public Error {
 public:
  ConfigError(std::string file, std::vector<Issue> issues);
  const std::string& file() const noexcept { return file_; }
  const std::vector<Issue>& issues() const noexcept { return issues_; }

 private:
  std::string file_;
  std::vector<Issue> issues_;
};

/// A data file (IMU or ground-truth CSV) that cannot be read; what() is "FILE:LINE: MESSAGE"
/// (line 0 when the problem is not about one line, e.g. a file that cannot be opened).
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
