// The tail the judging commands share (check, montecarlo, nees; docs/exit-codes.md): the work
// runs (reading, computing and writing the --report page, report_destination.h); if it fails,
// the failure is printed and its code returned (2 bad input, 3 internal, ReportFailure), and
// nothing goes to stdout, since nothing was judged; otherwise the judgment is printed on stdout,
// one JSON object with --json (the samples' warnings in it) or the command's table, and its exit
// code returned: 0 consistent, 1 inconsistent (nees has no verdict: 0).
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "imuconv/cli/commands.h"

namespace imuconv::cli {

/// What a judging command concluded, ready to print.
struct Judgment {
  std::function<nlohmann::json()> json;            ///< the --json object, before its warnings
  std::function<void(std::ostream&)> print_table;  ///< the summary without --json
  std::vector<std::string> warnings;  ///< the "warnings" of the JSON (already on stderr)
  int exit_code = 0;                  ///< exit_codes.h: kExitOk or kExitInconsistent
  /// A judgment whose output is a file already written (a montecarlo shard): nothing to print.
  bool printed_elsewhere = false;

  /// The --json object and the table of `result`, made by its command's two printers when the
  /// judgment is printed, after the work: both hold the result.
  template <typename Result>
  void SetResult(std::shared_ptr<const Result> result, nlohmann::json (*result_json)(const Result&),
                 void (*print_result)(std::ostream&, const Result&)) {
    json = [result, result_json] { return result_json(*result); };
    print_table = [result, print_result](std::ostream& out) { print_result(out, *result); };
  }
};

/// Runs `work` and prints what it concluded on std::cout (--json: `as_json`); returns the exit
/// code. A failure of `work` (a std::exception) is printed by ReportFailure and its code
/// returned; a UsageError goes through, to be reported as a usage error (SetCommandAction).
[[nodiscard]] int Judge(bool as_json, const std::function<Judgment()>& work);

}  // namespace imuconv::cli
