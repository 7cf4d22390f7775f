// `gtsam_pose3_vel`: the generic suite, its conversions derived by hand and the Expmap
// coupling beyond first order.
#include "../convention_suite.h"

IMUCONV_STATE_CONVENTION(gtsam_pose3_vel, "theta p v ba bg");

TEST(StateStructure, LeftToPose3VelKeepsWorldVelocity) {
  // Pose3 Expmap at 0: theta = R^T dtheta_l, t = Jl(0)^{-1} R^T dp_l = R^T dp_l; v world frame.
  ExpectConversion("left", "gtsam_pose3_vel", [](const ImuState& x) -> BlockEntries {
    const Mat3 Rt = x.R.transpose();
    return {{"theta", Rt}, {"p", Rt}};
  });
}

TEST(StateStructure, Pose3VelToNavStateAgreeToFirstOrderExceptVelocity) {
  // Jl(theta) t = t + O(|theta||t|): the Expmap coupling vanishes at first order.
  ExpectConversion("gtsam_pose3_vel", "gtsam_navstate", [](const ImuState& x) -> BlockEntries {
    return {{"v", x.R.transpose()}};
  });
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
  EXPECT_LE((y1.p - (x.p + x.R * so3::Jl(d.segment<3>(0)) * d.segment<3>(3))).cwiseAbs().maxCoeff(),
            1e-13);
  EXPECT_GT((y1.p - y2.p).norm(), 0.1);                 // |(Jl(theta) - I) t| ~ |theta||t|/2 ~ 0.5
  EXPECT_LE((y1.R - y2.R).cwiseAbs().maxCoeff(), 0.0);  // the same R^ Exp(theta), bit for bit
}
