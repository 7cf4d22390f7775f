// What the tests of imuconv check on other systems' own numbers share (issue 23): each
// system's test is a file of its own, tests/cli/check_anchor_<system>.cpp, which writes its
// anchor's preintegration of the case smooth-0, computed by its upstream code
// (tests/data/reference/anchors/README.md: how each file was built and what its fields mean),
// as a measurements file with nothing declared, and runs check on it here. Nothing in check was
// tuned to these numbers; what the tests assert is what the README says each system computes.
#pragma once

#include <initializer_list>
#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"
#include "json_rows.h"
#include "reference_case.h"

namespace imuconv::test::check_anchor {

using json = nlohmann::json;

/// The case every anchor's measurement is taken from.
inline const char* const kAnchorCase = "smooth-0";

/// One nonzero 3 x 3 block of a system's J_bias: `sign` times the anchor's matrix `key`, at
/// block row `row` (0 to 2, in the system's row order) and block column `col` (0 bg, 1 ba).
struct BiasJacobianBlock {
  int row, col;
  double sign;
  const char* key;
};

/// J_bias (9 x 6, zero but for `blocks`) from the anchor's preintegration object `p`.
inline Eigen::MatrixXd BiasJacobianOf(const json& p,
                                      std::initializer_list<BiasJacobianBlock> blocks) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(9, 6);
  for (const BiasJacobianBlock& b : blocks)
    J.block<3, 3>(3 * b.row, 3 * b.col) = b.sign * JsonMatrix(p.at(b.key));
  return J;
}

/// What a system gives of its preintegration, each in its own form: dt, the bias estimate it
/// linearized at, the increment (R, dp, dv), J_bias (9 x 6, columns [bg, ba], in its own row
/// order) and the covariance's rows.
struct AnchorNumbers {
  json dt, bg, ba, R, dp, dv;
  Eigen::MatrixXd J_bias;
  json cov;
};

/// `n` as one measurement of kAnchorCase's whole interval with nothing declared: J_bias and the
/// covariance in an "unknown" convention, so that check has to find the chart, order and
/// precision itself.
inline json UndeclaredMeasurement(const AnchorNumbers& n) {
  const json c = CaseJson(kAnchorCase);
  return {{"t_start", c["imu"].front()[0]},
          {"t_end", c["imu"].back()[0]},
          {"dt", n.dt},
          {"bias_estimate", {{"bg", n.bg}, {"ba", n.ba}}},
          {"delta", {{"R", n.R}, {"dp", n.dp}, {"dv", n.dv}}},
          {"J_bias", {{"convention", "unknown"}, {"matrix", JsonRows(n.J_bias)}}},
          {"cov", {{"convention", "unknown"}, {"matrix", n.cov}}}};
}

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
