// Increment (preintegrated measurement) conventions: the generic suite for each one, every
// ordered pair through the registry, and the known structure of particular conversions
// derived by hand from the paper's perturbations (eq. subeq:preint-error-dr..db,
// eq. residual-error, eq. preint-error-forster).
#include <cmath>

#include "convention_suite.h"

namespace {

using imuconv::Mat15;
using imuconv::Mat3;
using imuconv::PreintIncrement;
using imuconv::Vec15;
using imuconv::Vec3;
using imuconv::test::BlockBuilder;
using imuconv::test::Plugins;
using imuconv::test::PreintKind;
using imuconv::test::RelErr;
namespace so3 = imuconv::so3;

const auto* const kPrintWorst = ::testing::AddGlobalTestEnvironment(new imuconv::test::PrintWorstErrors);

IMUCONV_DEFINE_CONVENTION_SUITE(PreintConventionSuite, PreintKind)
IMUCONV_CONVENTION_SUITE(PreintConventionSuite, preint_reference);
IMUCONV_CONVENTION_SUITE(PreintConventionSuite, gtsam_tangent);
IMUCONV_CONVENTION_SUITE(PreintConventionSuite, gtsam_manifold);
IMUCONV_CONVENTION_SUITE(PreintConventionSuite, gtsam_manifold_jacobian);
IMUCONV_CONVENTION_SUITE(PreintConventionSuite, forster);

TEST(PreintConventions, EveryLoadedConventionRunsTheSuite) {
  imuconv::test::CheckEveryConventionHasSuite<PreintKind>("PreintConventionSuite");
}

TEST(PreintConventions, AllFourPlusReferenceAreLoaded) {
  for (const char* id : {"preint_reference", "gtsam_tangent", "gtsam_manifold", "gtsam_manifold_jacobian", "forster"})
    EXPECT_TRUE(Plugins().has(imuconv::PluginKind::PreintConvention, id)) << id;
}

TEST(PreintConventionPairs, ConversionsInvertAndMatchTheChartsDirectly) {
  imuconv::test::CheckAllPairs<PreintKind>();
}

TEST(PreintConventionPairs, RiddersComposedConversionMatchesAnalytic) {
  imuconv::test::CheckNumericalComposition<PreintKind>();
}

TEST(PreintConventions, BlockOrders) {
  using V = std::vector<std::string>;
  const auto blocks = [](const char* id) { return Plugins().info(imuconv::PluginKind::PreintConvention, id).blocks; };
  EXPECT_EQ(blocks("preint_reference"), (V{"theta", "p", "v", "bg", "ba"}));
  EXPECT_EQ(blocks("gtsam_tangent"), (V{"theta", "p", "v", "ba", "bg"}));
  EXPECT_EQ(blocks("gtsam_manifold"), (V{"theta", "p", "v", "ba", "bg"}));
  EXPECT_EQ(blocks("gtsam_manifold_jacobian"), (V{"theta", "p", "v", "ba", "bg"}));
  EXPECT_EQ(blocks("forster"), (V{"theta", "p", "v", "bg", "ba"}));
}

// GTSAM's ManifoldPreintegration states its covariance in c (gtsam_manifold) and its bias
// Jacobians in j (gtsam_manifold_jacobian); every other convention uses its own chart.
TEST(PreintConventions, BiasJacobianCharts) {
  const auto chart = [](const char* id) { return std::string(Plugins().preint_convention(id)->bias_jacobian_chart()); };
  EXPECT_EQ(chart("gtsam_manifold"), "gtsam_manifold_jacobian");
  EXPECT_EQ(chart("gtsam_manifold_jacobian"), "gtsam_manifold_jacobian");
  EXPECT_EQ(chart("gtsam_tangent"), "gtsam_tangent");
  EXPECT_EQ(chart("forster"), "forster");
  EXPECT_EQ(chart("preint_reference"), "preint_reference");
  EXPECT_EQ(Plugins().info(imuconv::PluginKind::PreintConvention, "gtsam_manifold").jacobian_convention,
            "gtsam_manifold_jacobian");
}

// ---- known structure --------------------------------------------------------------------

void ExpectConversion(const char* from, const char* to, const PreintIncrement& x, const Mat15& expected) {
  const Mat15 J = Plugins().preint_conversion(from, to, x);
  EXPECT_LE(RelErr(J, expected), imuconv::test::kStructureTol) << from << " -> " << to << "\ngot\n"
                                                                << J << "\nexpected\n" << expected;
}

BlockBuilder Expect(const char* from, const char* to) {
  return BlockBuilder(Plugins().preint_convention(to)->labels(), Plugins().preint_convention(from)->labels());
}

const Mat3 I3 = Mat3::Identity();

TEST(PreintStructure, TangentToManifoldJacobianIsTheRightJacobian) {
  for (const PreintIncrement& x : PreintKind::Points()) {
    // Exp(psi + dtheta) = Exp(psi) Exp(Jr(psi) dtheta + ...), psi = Log(dR^): the tangent
    // perturbation is Jr(psi) dtheta in the right-perturbation chart; dp, dv, Delta b (same
    // sign and order) pass through.
    ExpectConversion("gtsam_tangent", "gtsam_manifold_jacobian", x,
                     Expect("gtsam_tangent", "gtsam_manifold_jacobian")
                         .set("theta", "theta", so3::Jr(so3::Log(x.dR)))
                         .set("p", "p", I3)
                         .set("v", "v", I3)
                         .set("ba", "ba", I3)
                         .set("bg", "bg", I3)
                         .matrix());
  }
}

TEST(PreintStructure, ForsterIsMinusTheReference) {
  for (const PreintIncrement& x : PreintKind::Points()) {
    // Every block of eq. preint-error-forster enters with a minus sign, in the reference's
    // order, so the permutation is the identity and the conversion -I.
    EXPECT_TRUE(Plugins().preint_conversion("preint_reference", "forster", x).isApprox(-Mat15::Identity(), 0.0));
    EXPECT_TRUE(Plugins().preint_conversion("forster", "preint_reference", x).isApprox(-Mat15::Identity(), 0.0));
  }
}

TEST(PreintStructure, ReferenceToManifoldJacobianFlipsAndSwapsBiases) {
  for (const PreintIncrement& x : PreintKind::Points()) {
    const Mat15 J = Plugins().preint_conversion("preint_reference", "gtsam_manifold_jacobian", x);
    ExpectConversion("preint_reference", "gtsam_manifold_jacobian", x,
                     Expect("preint_reference", "gtsam_manifold_jacobian")
                         .set("theta", "theta", I3)
                         .set("p", "p", I3)
                         .set("v", "v", I3)
                         .set("ba", "ba", -I3)
                         .set("bg", "bg", -I3)
                         .matrix());
    // Raw indices: j's ba rows 9-11 read the reference's ba columns 12-14 with a minus sign.
    EXPECT_TRUE((J.block<3, 3>(9, 12).isApprox(-I3, 0.0)));
    EXPECT_TRUE((J.block<3, 3>(12, 9).isApprox(-I3, 0.0)));
  }
}

TEST(PreintStructure, ManifoldToManifoldJacobianRotatesTranslations) {
  for (const PreintIncrement& x : PreintKind::Points()) {
    // eq. residual-error vs subeq:preint-error-dp: dp_j = dR^ dp_c, dv_j = dR^ dv_c.
    ExpectConversion("gtsam_manifold", "gtsam_manifold_jacobian", x,
                     Expect("gtsam_manifold", "gtsam_manifold_jacobian")
                         .set("theta", "theta", I3)
                         .set("p", "p", x.dR)
                         .set("v", "v", x.dR)
                         .set("ba", "ba", I3)
                         .set("bg", "bg", I3)
                         .matrix());
  }
}

TEST(PreintStructure, ForsterToManifoldJacobianFlipsMotionKeepsBias) {
  for (const PreintIncrement& x : PreintKind::Points()) {
    // f and j have the same bias sign (Delta b = Delta b^ - db) but opposite motion signs.
    ExpectConversion("forster", "gtsam_manifold_jacobian", x,
                     Expect("forster", "gtsam_manifold_jacobian")
                         .set("theta", "theta", -I3)
                         .set("p", "p", -I3)
                         .set("v", "v", -I3)
                         .set("ba", "ba", I3)
                         .set("bg", "bg", I3)
                         .matrix());
  }
}

// gtsam_tangent parameterises dR by Log(dR) in (-pi, pi]: it is a chart only while
// |Log(dR^) + dtheta| < pi. Near the limit it still inverts; past it Log wraps around.
TEST(PreintStructure, TangentChartHoldsUpToPiAndWrapsBeyond) {
  const auto tangent = Plugins().preint_convention("gtsam_tangent");
  const Vec3 axis = Vec3(0.3, -0.5, 0.8).normalized();
  PreintIncrement x;
  x.dR = so3::Exp(3.0 * axis);
  Vec15 d = Vec15::Zero();
  d.segment<3>(0) = 0.1 * axis;  // |psi + dtheta| = 3.1 < pi
  PreintIncrement y;
  Vec15 back;
  tangent->retract(x, d, y);
  tangent->local(x, y, back);
  // Log near pi loses ~eps / (pi - |phi|) ~ 1e-14: still a tight inverse.
  EXPECT_LE((back - d).cwiseAbs().maxCoeff(), 1e-12);
  d.segment<3>(0) = 0.2 * axis;  // |psi + dtheta| = 3.2 > pi: Log returns the wrapped angle
  tangent->retract(x, d, y);
  tangent->local(x, y, back);
  EXPECT_GT((back - d).norm(), 1.0);  // wrapped: 3.2 axis comes back as (3.2 - 2 pi) axis
}

}  // namespace
