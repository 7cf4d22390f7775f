// State (error-state) conventions as a kind: the generic suite's tests (instantiated once per
// convention, in that convention's file), every ordered pair through the registry, and the
// block orders.
#include "suite.h"

namespace {

using imuconv::test::Plugins;
using imuconv::test::StateKind;

const auto* const kPrintWorst = ::testing::AddGlobalTestEnvironment(new imuconv::test::PrintWorstErrors);

}  // namespace

IMUCONV_DEFINE_CONVENTION_SUITE(StateConventionSuite, StateKind)

namespace {

TEST(StateConventions, EveryLoadedConventionRunsTheSuite) {
  imuconv::test::CheckEveryConventionHasSuite<StateKind>("StateConventionSuite");
}

TEST(StateConventions, AllSixPlusReferenceAreLoaded) {
  for (const char* id : {"left", "gtsam_navstate", "gtsam_pose3_vel", "forster", "openvins_jpl",
                         "right_invariant_se23", "left_invariant_se23"})
    EXPECT_TRUE(Plugins().has(imuconv::PluginKind::StateConvention, id)) << id;
}

TEST(StateConventionPairs, ConversionsInvertAndMatchTheChartsDirectly) {
  imuconv::test::CheckAllPairs<StateKind>();
}

TEST(StateConventionPairs, RiddersComposedConversionMatchesAnalytic) {
  imuconv::test::CheckNumericalComposition<StateKind>();
}

TEST(StateConventions, BlockOrders) {
  using V = std::vector<std::string>;
  const auto blocks = [](const char* id) { return Plugins().info(imuconv::PluginKind::StateConvention, id).blocks; };
  EXPECT_EQ(blocks("left"), (V{"p", "theta", "v", "bg", "ba"}));
  EXPECT_EQ(blocks("gtsam_navstate"), (V{"theta", "p", "v", "ba", "bg"}));
  EXPECT_EQ(blocks("gtsam_pose3_vel"), (V{"theta", "p", "v", "ba", "bg"}));
  EXPECT_EQ(blocks("forster"), (V{"theta", "p", "v", "bg", "ba"}));
  EXPECT_EQ(blocks("openvins_jpl"), (V{"theta", "p", "v", "bg", "ba"}));
  EXPECT_EQ(blocks("right_invariant_se23"), (V{"theta", "v", "p", "bg", "ba"}));
  EXPECT_EQ(blocks("left_invariant_se23"), (V{"theta", "v", "p", "bg", "ba"}));
}

}  // namespace
