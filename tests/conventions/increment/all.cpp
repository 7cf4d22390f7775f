// Increment (preintegrated measurement) conventions as a kind: the generic suite's tests
// (instantiated once per convention, in that convention's file), every ordered pair through
// the registry, the block orders and the bias-Jacobian charts.
#include "../convention_suite.h"

IMUCONV_DEFINE_CONVENTION_SUITE(IncrementConventionSuite, imuconv::test::IncrementKind);

namespace {

using imuconv::test::Plugins;

// The seven built-in conventions and the reference, each in the block order it documents.
TEST(PreintConventions, BuiltInsAndTheirBlockOrders) {
  imuconv::test::CheckBuiltInBlockOrders<imuconv::test::IncrementKind>(
      {{"preint_reference", "theta p v bg ba"},
       {"gtsam_tangent", "theta p v ba bg"},
       {"gtsam_manifold", "theta p v ba bg"},
       {"gtsam_manifold_jacobian", "theta p v ba bg"},
       {"forster", "theta p v bg ba"},
       {"vins_fusion", "p theta v ba bg"},
       {"basalt", "p theta v bg ba"},
       {"orb_slam3", "theta v p bg ba"},
       {"okvis2", "p theta v bg ba"}});
}

// GTSAM's ManifoldPreintegration states its covariance in c (gtsam_manifold) and its bias
// Jacobians in j (gtsam_manifold_jacobian); every other convention uses its own chart.
TEST(PreintConventions, BiasJacobianCharts) {
  const auto chart = [](const char* id) {
    return std::string(Plugins().increment_convention(id)->jacobian_convention());
  };
  EXPECT_EQ(chart("gtsam_manifold"), "gtsam_manifold_jacobian");
  EXPECT_EQ(chart("gtsam_manifold_jacobian"), "gtsam_manifold_jacobian");
  EXPECT_EQ(chart("gtsam_tangent"), "gtsam_tangent");
  EXPECT_EQ(chart("forster"), "forster");
  EXPECT_EQ(chart("vins_fusion"), "vins_fusion");
  EXPECT_EQ(chart("basalt"), "basalt");
  EXPECT_EQ(chart("orb_slam3"), "orb_slam3");
  EXPECT_EQ(chart("okvis2"), "okvis2");
  EXPECT_EQ(chart("preint_reference"), "preint_reference");
  EXPECT_EQ(Plugins()
                .info(imuconv::PluginKind::IncrementConvention, "gtsam_manifold")
                .jacobian_convention,
            "gtsam_manifold_jacobian");
}

}  // namespace
