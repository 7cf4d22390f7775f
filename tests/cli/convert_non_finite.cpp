// imuconv convert and imuconv conversion refuse a result that overflows (inputs that pass every
// check can: a state 1e200 m from the origin, squared in J S J^T), as a run does: exit 2 and a
// message naming what was converted, never an inf in the table or a null in --json.
#include <gtest/gtest.h>

#include <string>

#include "../pipeline/pipeline_test_util.h"

// A named namespace, not an anonymous one: the tests are compiled in unity batches, where
// this file's helpers and using-directives must not meet another file's.
namespace convert_non_finite_test {
using namespace imuconv::test;
using nlohmann::json;

/// examples/hover.state.json moved to the position (x, x, x) m.
std::string StateAt(const TempDir& tmp, double x) {
  json s = json::parse(ReadText(SourcePath("examples/hover.state.json")));
  s["p"] = {x, x, x};
  return tmp.write("state.json", s.dump());
}

std::string Identity15(const TempDir& tmp) {
  json rows = json::array();
  for (int i = 0; i < 15; ++i) {
    json r = json::array();
    for (int k = 0; k < 15; ++k) r.push_back(i == k ? 1.0 : 0.0);
    rows.push_back(r);
  }
  return tmp.write("I.json", rows.dump());
}

/// Runs `args` as text and with --json: each form exits 2, prints nothing on stdout and says
/// `says` on stderr.
void ExpectRefusedInTextAndJson(const std::string& args, const std::string& says,
                                const TempDir& tmp) {
  for (const std::string form : {"", " --json"}) {
    const CommandResult r = RunImuconv(args + form, tmp);
    EXPECT_EQ(r.exit_code, 2) << form << "\n" << r.out;
    EXPECT_EQ(r.out, "") << form;
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
  }
}

TEST(CliConvertNonFinite, AnOverflowingCovarianceIsRefusedInTextAndJson) {
  TempDir tmp;
  const std::string args =
      "convert --what covariance --from left --to right_invariant_se23 --state " +
      ShellQuote(StateAt(tmp, 1e200)) + " --matrix " + ShellQuote(Identity15(tmp));
  ExpectRefusedInTextAndJson(args,
                             "convert: the covariance from 'left' to 'right_invariant_se23' "
                             "produced a non-finite number (row ",
                             tmp);
}

TEST(CliConvertNonFinite, AFarButFiniteStateStillConverts) {
  // 1e100 m: J has entries of 1e100, J S J^T of 1e200, still below DBL_MAX (1.8e308).
  TempDir tmp;
  const CommandResult r = RunImuconv(
      "convert --what covariance --from left --to right_invariant_se23 --state " +
          ShellQuote(StateAt(tmp, 1e100)) + " --matrix " + ShellQuote(Identity15(tmp)) + " --json",
      tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Named: a range-for over a member of the temporary json::parse returns would read it freed.
  const json out = json::parse(r.out);
  for (const auto& row : out["result"]["matrix"])
    for (const auto& v : row) EXPECT_TRUE(v.is_number()) << v;
}

TEST(CliConvertNonFinite, AnOverflowingJacobianIsRefused) {
  // The body-frame chart rotates the world position: R^T p sums components of 1.7e308, past
  // DBL_MAX (1.8e308), while the state itself is finite.
  TempDir tmp;
  const CommandResult r = RunImuconv(
      "convert --what jacobian --from right_invariant_se23 --to gtsam_navstate --state " +
          ShellQuote(StateAt(tmp, 1.7e308)) + " --json",
      tmp);
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(
      r.err.find("convert: the jacobian from 'right_invariant_se23' to 'gtsam_navstate' produced a "
                 "non-finite number"),
      std::string::npos)
      << r.err;
}

TEST(CliConvertNonFinite, ConversionRefusesAnOverflowingJacobianToo) {
  TempDir tmp;
  const std::string args = "conversion --from right_invariant_se23 --to gtsam_navstate --state " +
                           ShellQuote(StateAt(tmp, 1.7e308));
  ExpectRefusedInTextAndJson(args,
                             "conversion: the jacobian from 'right_invariant_se23' to "
                             "'gtsam_navstate' produced a non-finite number (row ",
                             tmp);
}

}  // namespace convert_non_finite_test
