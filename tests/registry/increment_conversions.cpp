// The registry's one set of conversions, written once over the value type: increments get the
// covariance and transition conversions states have, and they mean the same thing.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "imuconv/registry.h"
#include "imuconv_test.h"
#include "scale_aware.h"

namespace {

using namespace imuconv;
using imuconv::test::Plugins;

// Every increment convention the registry loads from the built-in plugin directory (so a new
// system's is covered without a line here).
std::vector<std::string> IncrementCharts() {
  return Plugins().ids(PluginKind::IncrementConvention);
}

PreintIncrement SomeIncrement(double scale) {
  PreintIncrement d;
  d.dR = so3::Exp(Vec3(0.4, -0.9, 0.3) * scale);
  d.dp = Vec3(0.4, -0.2, 1.1) * scale;
  d.dv = Vec3(0.9, 0.3, -0.5) * scale;
  d.dbg = Vec3(1e-3, 0, -2e-3);
  d.dba = Vec3(1e-2, 2e-2, 0);
  return d;
}

// Symmetric positive definite, with correlations between every pair of blocks.
Mat15 SomeCovariance() {
  Mat15 A;
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j) A(i, j) = std::sin(1.0 + 0.7 * i + 1.3 * j);
  return A * A.transpose() + 0.1 * Mat15::Identity();
}

// A conversion and its inverse are 15x15 products with O(1) entries at these increments: their
// round-off is a few 1e-15 of the matrices' scale; 1e-11 leaves margin for it, while a wrong
// chart, order or sign is wrong by O(1).
constexpr double kRoundTrip = 1e-11;

double MaxRelative(const Mat15& ref, const Mat15& est) {
  return (ref - est).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff();
}

// convert_covariance at an increment is what imuconv convert and the pipeline's convert task
// computed by hand before they used it: J S J^T with J = conversion(from, to, delta), then
// 0.5 (C + C^T). Bit for bit, so their outputs are unchanged.
TEST(IncrementConversions, CovarianceIsTheSandwichTheCommandsComputed) {
  const PreintIncrement d = SomeIncrement(1.0);
  const Mat15 S = SomeCovariance();
  for (const std::string& a : IncrementCharts())
    for (const std::string& b : IncrementCharts()) {
      SCOPED_TRACE(a + " -> " + b);
      const Mat15 J = Plugins().conversion(a, b, d);
      Mat15 by_hand = J * S * J.transpose();
      by_hand = (0.5 * (by_hand + by_hand.transpose())).eval();
      const Mat15 got = Plugins().convert_covariance(a, b, d, S);
      EXPECT_EQ((got - by_hand).cwiseAbs().maxCoeff(), 0.0);
      // And back: the covariance it came from.
      EXPECT_LE(test::CorrelationScaleDiff(S, Plugins().convert_covariance(b, a, d, got)).d,
                kRoundTrip);
    }
}

// A map between increments (e.g. d Delta_new / d Delta_old) in one chart, carried into another:
// J_e Phi J_s^{-1}. Carried back it is Phi again, and the identity map at one increment stays
// the identity in every chart.
TEST(IncrementConversions, TransitionRoundTripsAndKeepsTheIdentity) {
  const PreintIncrement d_s = SomeIncrement(0.5), d_e = SomeIncrement(1.0);
  Mat15 Phi;
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j)
      Phi(i, j) = (i == j ? 1.0 : 0.0) + 0.1 * std::cos(0.3 * i - 0.8 * j);
  for (const std::string& a : IncrementCharts())
    for (const std::string& b : IncrementCharts()) {
      SCOPED_TRACE(a + " -> " + b);
      const Mat15 there = Plugins().convert_transition(a, b, d_s, d_e, Phi);
      EXPECT_LE(MaxRelative(Phi, Plugins().convert_transition(b, a, d_s, d_e, there)), kRoundTrip);
      const Mat15 identity = Plugins().convert_transition(a, b, d_s, d_s, Mat15::Identity());
      EXPECT_LE((identity - Mat15::Identity()).cwiseAbs().maxCoeff(), kRoundTrip);
    }
}

// to_reference and from_reference compose to conversion, for increments as for states.
TEST(IncrementConversions, ReferenceFactorsComposeToTheConversion) {
  const PreintIncrement d = SomeIncrement(1.0);
  for (const std::string& a : IncrementCharts())
    for (const std::string& b : IncrementCharts()) {
      SCOPED_TRACE(a + " -> " + b);
      const Mat15 composed = Plugins().from_reference(b, d) * Plugins().to_reference(a, d);
      EXPECT_LE(MaxRelative(Plugins().conversion(a, b, d), composed), kRoundTrip);
    }
}

// The value's type chooses the kind: a state convention's id at an increment is unknown (and
// the message lists the increment conventions), not a state chart applied to an increment.
TEST(IncrementConversions, AnIdOfTheOtherKindIsRefused) {
  try {
    (void)Plugins().convert_covariance("gtsam_navstate", "forster", SomeIncrement(1.0),
                                       SomeCovariance());
    ADD_FAILURE() << "a state convention was taken at an increment";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("gtsam_navstate"), std::string::npos) << m;
    EXPECT_NE(m.find("preint_convention"), std::string::npos) << m;
  }
  try {
    (void)Plugins().conversion("gtsam_manifold", "left", ImuState{});
    ADD_FAILURE() << "an increment convention was taken at a state";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("gtsam_manifold"), std::string::npos) << e.what();
  }
}

}  // namespace
