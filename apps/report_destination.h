// --report OUT.html of the judging commands (check, montecarlo, nees) and of experiment: one
// destination, examined when the command starts (report::ReportOutput: a directory, an
// unwritable place or an input's own name fails before any work), and at the end the page
// written atomically and named on stderr. Without --report every step is nothing, so a
// command says what its report would hold once and needs no branch of its own.
#pragma once

#include <functional>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "imuconv/cli/commands.h"
#include "imuconv/report/html_document.h"
#include "imuconv/report/report_output.h"

namespace imuconv::cli {

/// Adds --report OUT.html to a command, its value checked by OutputPathCheck; its help is
/// "Also write a self-contained HTML report: " and then `contents`.
CLI::Option* AddReportOption(CLI::App& sub, std::string& path, const std::string& contents);

/// The inputs a report page lists, (role, path), for each of `options` whose path was given
/// (is not empty), in their order.
std::vector<std::pair<std::string, std::string>> GivenInputs(
    std::initializer_list<std::pair<const char*, const std::string*>> options);

class ReportDestination {
 public:
  /// `path` empty: no report was asked for. Otherwise throws imuconv::Error "--report PATH: ..."
  /// when PATH cannot be the report.
  explicit ReportDestination(const std::string& path);

  bool wanted() const { return out_.has_value(); }

  /// Throws imuconv::Error when the report would replace `input` (described as `role`); an
  /// empty `input` (an option not given) is no file and is skipped.
  void RefuseIfSame(const std::string& input, const std::string& role) const;
  /// Throws imuconv::Error when the report would replace a shared object loaded (a plugin).
  void RefuseIfLoadedObject() const;
  /// Throws imuconv::Error when `other`, another output of the command (given as
  /// `other_role`, "-o"), is the report's file too, however either is spelled.
  void RefuseIfSameOutput(const pipeline::OutputFile& other, const std::string& other_role) const;

  /// Builds the page (only when a report is wanted), checks the loaded objects once more (the
  /// plugins are loaded by now), writes it atomically and, unless -q, says "wrote PATH" on
  /// stderr (`announce` false: the caller says it later, as experiment does after its table).
  void Write(const std::function<report::HtmlDocument()>& page, const CommandContext& ctx,
             bool announce = true);
  /// "wrote PATH" on stderr, unless -q or no report was written.
  void Announce(const CommandContext& ctx) const;

 private:
  std::optional<report::ReportOutput> out_;
  bool written_ = false;
};

}  // namespace imuconv::cli
