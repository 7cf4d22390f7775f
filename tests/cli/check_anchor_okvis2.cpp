// imuconv check on OKVIS2's own numbers (check_anchor.h): explained by its own scheme,
// `okvis2`, in its order and chart.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <string>

#include "check_anchor.h"

namespace {
using namespace imuconv::test::check_anchor;
using nlohmann::json;

/// OKVIS2's ImuError preintegration as a measurement: the increment Delta_R,
/// acc_doubleintegral, acc_integral; the covariance P_delta as it is (its order [p, alpha, v,
/// bg, ba], Delta_C = Exp(dalpha) Delta_C^, left, in the first frame). J_bias in OKVIS's own
/// row order [p, alpha, v], columns [bg, ba], from the residual's first-order correction:
/// dp/dbg = dp_db_g, dp/dba = -C_doubleintegral, dalpha/dbg = -dalpha_db_g (Dq =
/// exp(-dalpha_db_g dbg) Delta q), dv/dbg = dv_db_g, dv/dba = -C_integral. Nothing declared.
json Okvis2Measurement() {
  const json a = AnchorJson("okvis2", kAnchorCase);
  const json& p = a["imu_error"]["preintegration"];
  const json& start = a["inputs"]["state_start"];
  const Eigen::MatrixXd J = BiasJacobianOf(p, {{0, 0, +1, "dp_db_g"},
                                               {0, 1, -1, "C_doubleintegral"},
                                               {1, 0, -1, "dalpha_db_g"},
                                               {2, 0, +1, "dv_db_g"},
                                               {2, 1, -1, "C_integral"}});
  return UndeclaredMeasurement({a["inputs"]["Delta_t"], start["bg"], start["ba"], p["Delta_R"],
                                p["acc_doubleintegral"], p["acc_integral"], J,
                                p["P_delta"]["matrix"]});
}

TEST(CheckAnchors, Okvis2IsExplainedByItsOwnScheme) {
  // With the `okvis2` preintegrator among check's reference schemes (ImuError's
  // redoPreintegration, its F_delta as coded), OKVIS2's own numbers are explained exactly: the
  // same computation, so every difference is round-off (1e-9, as for check's own measurements;
  // measured 6e-14), in its order [p, alpha, v, bg, ba] with alpha a left perturbation in the
  // first frame. That chart is both `okvis2` and `basalt` (the same perturbation): check names
  // one and lists the other as the same numbers.
  const AnchorChecked c = RunCheck(Okvis2Measurement(), "okvis2");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const json& m = c.m;
  std::printf("%s\n%s\n", m["best"].dump().c_str(), c.findings.c_str());
  EXPECT_EQ(m["precision"]["numbers"], "float64");
  EXPECT_EQ(m["best"]["scheme"], "okvis2");
  EXPECT_EQ(m["best"]["blocks"], json({"p", "theta", "v", "bg", "ba"}));
  const std::set<std::string> same_chart = {"okvis2", "basalt"};
  EXPECT_TRUE(same_chart.count(m["best"]["convention"].get<std::string>())) << m["best"].dump();
  const std::string other = m["best"]["convention"] == "okvis2" ? "basalt" : "okvis2";
  EXPECT_NE(c.findings.find("the covariance in " + other + " [p, theta, v, bg, ba]"),
            std::string::npos)
      << c.findings;
  for (const char* part : {"delta", "J_bias", "cov"})
    EXPECT_LE(m["best"][part]["max_d"].get<double>(), 1e-9) << part;
  EXPECT_TRUE(m["block_findings"].empty()) << m["block_findings"].dump(1);
  EXPECT_TRUE(m["unexplained_blocks"].empty()) << m["unexplained_blocks"].dump(1);
}

}  // namespace
