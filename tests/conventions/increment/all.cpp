// Increment (preintegrated measurement) conventions as a kind: the generic suite's tests
// (instantiated once per convention, in that convention's file), every ordered pair through
// the registry, the block orders and the bias-Jacobian charts.
#include "../convention_suite.h"

IMUCONV_DEFINE_CONVENTION_SUITE(IncrementConventionSuite, imuconv::test::IncrementKind);

namespace {

using imuconv::test::Plugins;

// Each convention declares the block order it documents in its own test file
// (IMUCONV_CONVENTION_BLOCK_ORDER, increment/<id>.cpp): the loaded plugins agree with every
// declaration, and every increment convention loaded from the built-in plugin directory has one.
TEST(PreintConventions, BuiltInsAndTheirBlockOrders) {
  imuconv::test::CheckDeclaredBlockOrders<imuconv::test::IncrementKind>(
      "its own test file, tests/conventions/increment/<id>.cpp");
}

// Each convention declares the chart of its bias Jacobians in its own test file
// (IMUCONV_BIAS_JACOBIAN_CHART): the plugin and the registry's record of it say the same, and
// every loaded increment convention has a declaration.
TEST(PreintConventions, BiasJacobianCharts) {
  imuconv::test::DeclaredFacts<imuconv::test::BiasJacobianChart>::CheckAll(
      Plugins(), imuconv::PluginKind::IncrementConvention,
      "its own test file, tests/conventions/increment/<id>.cpp",
      "IMUCONV_BIAS_JACOBIAN_CHART(<id>, \"<chart>\")",
      [](const std::string& id, const char* chart) {
        EXPECT_EQ(std::string(Plugins().increment_convention(id)->jacobian_convention()), chart)
            << id;
        EXPECT_EQ(Plugins().info(imuconv::PluginKind::IncrementConvention, id).jacobian_convention,
                  chart)
            << id;
      });
}

}  // namespace
