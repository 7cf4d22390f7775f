// State (error-state) conventions: the generic suite for each one, every ordered pair
// through the registry, and the known structure of particular conversions derived by hand.
#include "convention_suite.h"

namespace {

using imuconv::ImuState;
using imuconv::Mat15;
using imuconv::Mat3;
using imuconv::test::BlockBuilder;
using imuconv::test::Plugins;
using imuconv::test::RelErr;
using imuconv::test::StateKind;
namespace so3 = imuconv::so3;

const auto* const kPrintWorst = ::testing::AddGlobalTestEnvironment(new imuconv::test::PrintWorstErrors);

IMUCONV_DEFINE_CONVENTION_SUITE(StateConventionSuite, StateKind)
IMUCONV_CONVENTION_SUITE(StateConventionSuite, left);
IMUCONV_CONVENTION_SUITE(StateConventionSuite, gtsam_navstate);
IMUCONV_CONVENTION_SUITE(StateConventionSuite, gtsam_pose3_vel);
IMUCONV_CONVENTION_SUITE(StateConventionSuite, forster);
IMUCONV_CONVENTION_SUITE(StateConventionSuite, openvins_jpl);
IMUCONV_CONVENTION_SUITE(StateConventionSuite, right_invariant_se23);
IMUCONV_CONVENTION_SUITE(StateConventionSuite, left_invariant_se23);

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

// ---- known structure --------------------------------------------------------------------

// Expected conversion(from, to, x) built block by block; compares with the registry's.
void ExpectConversion(const char* from, const char* to, const ImuState& x, const Mat15& expected) {
  const Mat15 J = Plugins().conversion(from, to, x);
  EXPECT_LE(RelErr(J, expected), imuconv::test::kStructureTol) << from << " -> " << to << "\ngot\n"
                                                                << J << "\nexpected\n" << expected;
}

BlockBuilder Expect(const char* from, const char* to) {
  return BlockBuilder(Plugins().state_convention(to)->labels(), Plugins().state_convention(from)->labels());
}

const Mat3 I3 = Mat3::Identity();

TEST(StateStructure, LeftToNavStateRotatesIntoTheBodyFrame) {
  for (const ImuState& x : StateKind::Points()) {
    const Mat3 Rt = x.R.transpose();
    // R^ Exp(dtheta) = Exp(dtheta_l) R^  =>  dtheta = R^T dtheta_l; dp = R^T dp_l, dv = R^T dv_l
    // (NavState's body-frame translations); biases unchanged but swapped to [ba, bg].
    ExpectConversion("left", "gtsam_navstate", x,
                     Expect("left", "gtsam_navstate")
                         .set("theta", "theta", Rt)
                         .set("p", "p", Rt)
                         .set("v", "v", Rt)
                         .set("ba", "ba", I3)
                         .set("bg", "bg", I3)
                         .matrix());
    // The same in raw indices: NavState's rotation rows 0-2 read left's theta columns 3-5,
    // its ba rows 9-11 read left's ba columns 12-14, its bg rows 12-14 left's bg columns 9-11.
    const Mat15 J = Plugins().conversion("left", "gtsam_navstate", x);
    EXPECT_LE(RelErr(J.block<3, 3>(0, 3), Rt), imuconv::test::kStructureTol);
    EXPECT_TRUE((J.block<3, 3>(9, 12).isIdentity(0.0)));
    EXPECT_TRUE((J.block<3, 3>(12, 9).isIdentity(0.0)));
  }
}

TEST(StateStructure, LeftToPose3VelKeepsWorldVelocity) {
  for (const ImuState& x : StateKind::Points()) {
    const Mat3 Rt = x.R.transpose();
    // Pose3 Expmap at 0: theta = R^T dtheta_l, t = Jl(0)^{-1} R^T dp_l = R^T dp_l; v world frame.
    ExpectConversion("left", "gtsam_pose3_vel", x,
                     Expect("left", "gtsam_pose3_vel")
                         .set("theta", "theta", Rt)
                         .set("p", "p", Rt)
                         .set("v", "v", I3)
                         .set("ba", "ba", I3)
                         .set("bg", "bg", I3)
                         .matrix());
  }
}

TEST(StateStructure, LeftToForster) {
  for (const ImuState& x : StateKind::Points()) {
    const Mat3 Rt = x.R.transpose();
    // Right rotation and body-frame position (R^T), world velocity, biases in place.
    ExpectConversion("left", "forster", x,
                     Expect("left", "forster")
                         .set("theta", "theta", Rt)
                         .set("p", "p", Rt)
                         .set("v", "v", I3)
                         .set("bg", "bg", I3)
                         .set("ba", "ba", I3)
                         .matrix());
  }
}

TEST(StateStructure, LeftToOpenVinsJpl) {
  for (const ImuState& x : StateKind::Points()) {
    // JPL's left update of q_GtoI is a right update of R = R_GtoI^T (R^T dtheta_l to first
    // order: 2 atan(s/2)/s = 1 + O(s^2)); p and v are global-frame additive like left's.
    ExpectConversion("left", "openvins_jpl", x,
                     Expect("left", "openvins_jpl")
                         .set("theta", "theta", x.R.transpose())
                         .set("p", "p", I3)
                         .set("v", "v", I3)
                         .set("bg", "bg", I3)
                         .set("ba", "ba", I3)
                         .matrix());
  }
}

TEST(StateStructure, LeftToRightInvariantCouplesRotationIntoTranslations) {
  for (const ImuState& x : StateKind::Points()) {
    // Exp(phi) v^ + Jl(phi) nu = v^ + dv_l  =>  nu = dv_l - [phi]x v^ = dv_l + [v^]x dtheta_l.
    ExpectConversion("left", "right_invariant_se23", x,
                     Expect("left", "right_invariant_se23")
                         .set("theta", "theta", I3)
                         .set("v", "theta", so3::skew(x.v))
                         .set("v", "v", I3)
                         .set("p", "theta", so3::skew(x.p))
                         .set("p", "p", I3)
                         .set("bg", "bg", I3)
                         .set("ba", "ba", I3)
                         .matrix());
  }
}

TEST(StateStructure, LeftToLeftInvariant) {
  for (const ImuState& x : StateKind::Points()) {
    const Mat3 Rt = x.R.transpose();
    // X^ Exp(xi) at first order: R^ phi, R^ nu, R^ rho.
    ExpectConversion("left", "left_invariant_se23", x,
                     Expect("left", "left_invariant_se23")
                         .set("theta", "theta", Rt)
                         .set("v", "v", Rt)
                         .set("p", "p", Rt)
                         .set("bg", "bg", I3)
                         .set("ba", "ba", I3)
                         .matrix());
  }
}

TEST(StateStructure, LeftToRightInvariantIsTheSe23Adjoint) {
  for (const ImuState& x : StateKind::Points()) {
    // X Exp(xi) = Exp(Ad_X xi) X with Ad_X = [[R, 0, 0], [[v]x R, R, 0], [[p]x R, 0, R]] in
    // the order [phi, nu, rho]; biases are outside the group.
    const Mat3& R = x.R;
    ExpectConversion("left_invariant_se23", "right_invariant_se23", x,
                     Expect("left_invariant_se23", "right_invariant_se23")
                         .set("theta", "theta", R)
                         .set("v", "theta", so3::skew(x.v) * R)
                         .set("v", "v", R)
                         .set("p", "theta", so3::skew(x.p) * R)
                         .set("p", "p", R)
                         .set("bg", "bg", I3)
                         .set("ba", "ba", I3)
                         .matrix());
  }
}

TEST(StateStructure, ForsterToNavStateDiffersInVelocityFrame) {
  for (const ImuState& x : StateKind::Points()) {
    // Same rotation and position perturbation; Forster's world-frame dv is R^ dv_nav.
    ExpectConversion("forster", "gtsam_navstate", x,
                     Expect("forster", "gtsam_navstate")
                         .set("theta", "theta", I3)
                         .set("p", "p", I3)
                         .set("v", "v", x.R.transpose())
                         .set("ba", "ba", I3)
                         .set("bg", "bg", I3)
                         .matrix());
  }
}

TEST(StateStructure, Pose3VelToNavStateAgreeToFirstOrderExceptVelocity) {
  for (const ImuState& x : StateKind::Points()) {
    // Jl(theta) t = t + O(|theta||t|): the Expmap coupling vanishes at first order.
    ExpectConversion("gtsam_pose3_vel", "gtsam_navstate", x,
                     Expect("gtsam_pose3_vel", "gtsam_navstate")
                         .set("theta", "theta", I3)
                         .set("p", "p", I3)
                         .set("v", "v", x.R.transpose())
                         .set("ba", "ba", I3)
                         .set("bg", "bg", I3)
                         .matrix());
  }
}

TEST(StateStructure, ForsterToOpenVinsJplAgreeOnRotation) {
  for (const ImuState& x : StateKind::Points()) {
    // Both perturb R on the right; OpenVINS's position is global (R^ dp_forster).
    ExpectConversion("forster", "openvins_jpl", x,
                     Expect("forster", "openvins_jpl")
                         .set("theta", "theta", I3)
                         .set("p", "p", x.R)
                         .set("v", "v", I3)
                         .set("bg", "bg", I3)
                         .set("ba", "ba", I3)
                         .matrix());
  }
}

// The charts differ beyond first order even where their Jacobians agree: a check that the
// second-order structure is really each library's (the Jacobian tests cannot see it).
TEST(StateStructure, Pose3ExpmapCouplesTranslationToRotation) {
  const auto pose3 = Plugins().state_convention("gtsam_pose3_vel");
  const auto nav = Plugins().state_convention("gtsam_navstate");
  const ImuState x = StateKind::Points()[2];
  imuconv::Vec15 d = imuconv::Vec15::Zero();
  d.segment<3>(0) = imuconv::Vec3(0.3, -0.2, 0.5);  // theta
  d.segment<3>(3) = imuconv::Vec3(1.0, 2.0, -1.5);  // t
  ImuState y1, y2;
  pose3->retract(x, d, y1);
  nav->retract(x, d, y2);
  // Pose3::Expmap: p = p^ + R^ Jl(theta) t; NavState: p = p^ + R^ dp. Tolerance: a few
  // ulps of |p| ~ 20 (the same products in another association).
  EXPECT_LE((y1.p - (x.p + x.R * so3::Jl(d.segment<3>(0)) * d.segment<3>(3))).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_GT((y1.p - y2.p).norm(), 0.1);  // |(Jl(theta) - I) t| ~ |theta||t|/2 ~ 0.5
  EXPECT_LE((y1.R - y2.R).cwiseAbs().maxCoeff(), 0.0);  // the same R^ Exp(theta), bit for bit
}

}  // namespace
