// What the tests of imuconv check on other systems' own numbers share (issue 23): each
// system's test is a file of its own, tests/cli/check_anchor_<system>.cpp, which writes its
// anchor's preintegration of the case smooth-0, computed by its upstream code
// (tests/data/reference/anchors/README.md: how each file was built and what its fields mean),
// as a measurements file with nothing declared, and runs check on it here. Nothing in check was
// tuned to these numbers; what the tests assert is what the README says each system computes.
#pragma once

#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"

namespace imuconv::test::check_anchor {

using json = nlohmann::json;

/// The case every anchor's measurement is taken from.
inline const char* const kAnchorCase = "smooth-0";

struct AnchorChecked {
  int exit_code = -1;
  json m;  // measurement 0
  std::string err, findings;
};

inline AnchorChecked RunCheck(const json& m, const std::string& name) {
  static TempDir tmp;
  const std::string file = tmp.write(name + ".json", json{{"measurements", {m}}}.dump());
  const CommandResult r = RunImuconv(
      "check " + ShellQuote(file) + " --case " +
          ShellQuote(DataPath(std::string("reference/cases/") + kAnchorCase + ".json")) + " --json",
      tmp);
  AnchorChecked c{r.exit_code, json(), r.err, ""};
  if (r.exit_code == 0 || r.exit_code == 1) {
    c.m = json::parse(r.out)["measurements"][0];
    for (const auto& f : c.m["findings"]) c.findings += f.get<std::string>() + "\n";
  }
  return c;
}

}  // namespace imuconv::test::check_anchor
