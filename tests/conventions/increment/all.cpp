// Increment (preintegrated measurement) conventions as a kind: the generic suite's tests
// (instantiated once per convention, in that convention's file), every ordered pair through
// the registry, the block orders and the bias-Jacobian charts.
#include "suite.h"

namespace {

using imuconv::test::Plugins;
using imuconv::test::IncrementKind;

const auto* const kPrintWorst = ::testing::AddGlobalTestEnvironment(new imuconv::test::PrintWorstErrors);

}  // namespace

IMUCONV_DEFINE_CONVENTION_SUITE(IncrementConventionSuite, IncrementKind)

namespace {

TEST(PreintConventions, EveryLoadedConventionRunsTheSuite) {
  imuconv::test::CheckEveryConventionHasSuite<IncrementKind>("IncrementConventionSuite");
}

TEST(PreintConventions, AllFourPlusReferenceAreLoaded) {
  for (const char* id : {"preint_reference", "gtsam_tangent", "gtsam_manifold", "gtsam_manifold_jacobian", "forster"})
    EXPECT_TRUE(Plugins().has(imuconv::PluginKind::IncrementConvention, id)) << id;
}

TEST(PreintConventionPairs, ConversionsInvertAndMatchTheChartsDirectly) {
  imuconv::test::CheckAllPairs<IncrementKind>();
}

TEST(PreintConventionPairs, RiddersComposedConversionMatchesAnalytic) {
  imuconv::test::CheckNumericalComposition<IncrementKind>();
}

TEST(PreintConventions, BlockOrders) {
  using V = std::vector<std::string>;
  const auto blocks = [](const char* id) { return Plugins().info(imuconv::PluginKind::IncrementConvention, id).blocks; };
  EXPECT_EQ(blocks("preint_reference"), (V{"theta", "p", "v", "bg", "ba"}));
  EXPECT_EQ(blocks("gtsam_tangent"), (V{"theta", "p", "v", "ba", "bg"}));
  EXPECT_EQ(blocks("gtsam_manifold"), (V{"theta", "p", "v", "ba", "bg"}));
  EXPECT_EQ(blocks("gtsam_manifold_jacobian"), (V{"theta", "p", "v", "ba", "bg"}));
  EXPECT_EQ(blocks("forster"), (V{"theta", "p", "v", "bg", "ba"}));
}

// GTSAM's ManifoldPreintegration states its covariance in c (gtsam_manifold) and its bias
// Jacobians in j (gtsam_manifold_jacobian); every other convention uses its own chart.
TEST(PreintConventions, BiasJacobianCharts) {
  const auto chart = [](const char* id) { return std::string(Plugins().increment_convention(id)->jacobian_convention()); };
  EXPECT_EQ(chart("gtsam_manifold"), "gtsam_manifold_jacobian");
  EXPECT_EQ(chart("gtsam_manifold_jacobian"), "gtsam_manifold_jacobian");
  EXPECT_EQ(chart("gtsam_tangent"), "gtsam_tangent");
  EXPECT_EQ(chart("forster"), "forster");
  EXPECT_EQ(chart("preint_reference"), "preint_reference");
  EXPECT_EQ(Plugins().info(imuconv::PluginKind::IncrementConvention, "gtsam_manifold").jacobian_convention,
            "gtsam_manifold_jacobian");
}

}  // namespace
