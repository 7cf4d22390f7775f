// `gtsam_navstate`: the generic suite and the conversion from `left` derived by hand.
#include "../convention_suite.h"

IMUCONV_STATE_CONVENTION(gtsam_navstate, "theta p v ba bg");

TEST(StateStructure, LeftToNavStateRotatesIntoTheBodyFrame) {
  // R^ Exp(dtheta) = Exp(dtheta_l) R^  =>  dtheta = R^T dtheta_l; dp = R^T dp_l, dv = R^T dv_l
  // (NavState's body-frame translations); biases unchanged but swapped to [ba, bg].
  ExpectConversion("left", "gtsam_navstate", [](const ImuState& x) -> BlockEntries {
    const Mat3 Rt = x.R.transpose();
    return {{"theta", Rt}, {"p", Rt}, {"v", Rt}};
  });
  for (const ImuState& x : StateKind::Points()) {
    // The same in raw indices: NavState's rotation rows 0-2 read left's theta columns 3-5,
    // its ba rows 9-11 read left's ba columns 12-14, its bg rows 12-14 left's bg columns 9-11.
    const Mat15 J = Plugins().conversion("left", "gtsam_navstate", x);
    EXPECT_LE(RelErr(J.block<3, 3>(0, 3), x.R.transpose()), kStructureTol);
    EXPECT_TRUE((J.block<3, 3>(9, 12).isIdentity(0.0)));
    EXPECT_TRUE((J.block<3, 3>(12, 9).isIdentity(0.0)));
  }
}
