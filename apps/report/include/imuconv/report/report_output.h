// Where --report OUT.html goes: the project's output file (pipeline/output_file.h), examined
// when made, before any work, so a directory, a missing or unwritable directory or an input's
// own name is refused at once and not after a long run; written atomically at the end, so no
// half-written report is ever left (a failing or interrupted run leaves none). The report
// never goes to standard output, which holds the command's table or JSON.
#pragma once

#include <memory>
#include <string>

namespace imuconv::pipeline {
class OutputFile;
}

namespace imuconv::report {

class HtmlDocument;

class ReportOutput {
 public:
  /// Throws imuconv::Error "--report PATH: ..." when PATH cannot be the report.
  explicit ReportOutput(const std::string& path);
  ~ReportOutput();
  ReportOutput(const ReportOutput&) = delete;
  ReportOutput& operator=(const ReportOutput&) = delete;

  /// Throws imuconv::Error when the report would replace `input` (described as `role`).
  void RefuseIfSame(const std::string& input, const std::string& role) const;
  /// Also every shared object loaded (the plugins).
  void RefuseIfLoadedObject() const;
  /// Throws imuconv::Error when `other`, another output of the command (`other_role`: "-o"),
  /// would write the report's file too (pipeline::OutputFile::refuse_if_same_output).
  void RefuseIfSameOutput(const pipeline::OutputFile& other, const std::string& other_role) const;

  /// Writes the document and commits it. Throws imuconv::Error naming the path on failure.
  void Write(const HtmlDocument& doc);

  const std::string& path() const;

 private:
  std::unique_ptr<pipeline::OutputFile> file_;
};

}  // namespace imuconv::report
