// imuconv check on ORB-SLAM3's own numbers (check_anchor.h): recognized as its own scheme,
// `orb_slam3`, in float32.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <string>

#include "check_anchor.h"

namespace {
using namespace imuconv::test::check_anchor;
using nlohmann::json;

/// ORB-SLAM3's IMU::Preintegrated (float32 throughout, held as doubles) as a measurement:
/// the increment dR, dP, dV; J_bias rows [theta, p, v] (right perturbation, the README's
/// dR(b) = dR Exp(JRg dbg), dV(b) = dV + JVg dbg + JVa dba, dP likewise: d/d(bias estimate)),
/// columns [bg, ba]; the covariance C as it is, in its order [theta, v, p, bg, ba]; dt its
/// float sum of the steps dT; the bias estimate ORB linearized at (rounded to float). No
/// chart, order or precision is declared.
json OrbSlam3Measurement() {
  const json a = AnchorJson("orb-slam3", kAnchorCase);
  const json& p = a["preintegration"];
  const json& bias = a["inputs"]["bias_lin_float"];
  const Eigen::MatrixXd J = BiasJacobianOf(p, {{0, 0, +1, "JRg"},
                                               {1, 0, +1, "JPg"},
                                               {1, 1, +1, "JPa"},
                                               {2, 0, +1, "JVg"},
                                               {2, 1, +1, "JVa"}});
  return UndeclaredMeasurement(
      {p["dT"], bias["bg"], bias["ba"], p["dR"], p["dP"], p["dV"], J, p["C"]["matrix"]});
}

// With the `orb_slam3` preintegrator registered, check has ORB-SLAM3's own scheme among its
// references, and recognizes the original's numbers as that scheme's. (Before it was, check
// explained them as `midpoint` with the state-bias cross terms found missing; that finding's
// mechanism is exercised on its own in check_blocks.cpp.)
TEST(CheckAnchors, OrbSlam3IsRecognizedAsItsOwnScheme) {
  const AnchorChecked c = RunCheck(OrbSlam3Measurement(), "orb-slam3");
  ASSERT_EQ(c.exit_code, 0) << c.err << c.findings;
  const json& m = c.m;
  std::printf("%s\n%s\n", m["best"].dump().c_str(), c.findings.c_str());
  EXPECT_EQ(m["precision"]["numbers"], "float32");
  EXPECT_TRUE(m["precision"]["inferred"].get<bool>());
  // dT is ORB's float sum of 2000 steps of 5 ms: 10.000181198120117 s, 1.8e-4 s off the
  // interval, within the 1.2e-3 s such a sum can lose (2000 x 2^-24 x 10 s).
  ASSERT_TRUE(m["dt_difference"].is_number());
  EXPECT_NEAR(m["dt_difference"].get<double>(), 10.000181198120117 - 10.0, 1e-9);
  EXPECT_NEAR(m["dt_rounding_bound"].get<double>(), 2000 * std::ldexp(1.0, -24) * 10.0, 1e-9);
  EXPECT_NE(c.findings.find("within what a float32 sum"), std::string::npos) << c.findings;
  EXPECT_EQ(m["best"]["scheme"], "orb_slam3");
  EXPECT_EQ(m["best"]["blocks"], json({"theta", "v", "p", "bg", "ba"}));
  // The same float computation: J_bias equal; the increment moved only by the measurements
  // form's reading of R as Exp(Log(R)) (a float rotation is orthogonal to about 1e-7); C by
  // half its float asymmetry (the reference is symmetrized, ORB's C is not: 1.4e-6 of an entry
  // on smooth-0). Bound: the 1e-4 for single precision (measured 1.9e-7 and 7e-7).
  EXPECT_LE(m["best"]["J_bias"]["max_d"].get<double>(), 1e-4);
  EXPECT_LE(m["best"]["delta"]["max_d"].get<double>(), 1e-4);
  EXPECT_LE(m["best"]["cov"]["max_d"].get<double>(), 1e-4);
  EXPECT_TRUE(m["block_findings"].empty()) << m["block_findings"].dump(1);
  EXPECT_TRUE(m["unexplained_blocks"].empty()) << m["unexplained_blocks"].dump(1);
}

}  // namespace
