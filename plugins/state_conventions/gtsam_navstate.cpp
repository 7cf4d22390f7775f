// `gtsam_navstate`: the chart of gtsam::NavState::retract / localCoordinates (the state of
// GTSAM's ImuFactor2 and of PreintegrationBase::predict), with the biases of
// gtsam::imuBias::ConstantBias added, accelerometer first. Paper eq.
// subeq:navstate-drp..subeq:navstate-dbg:
//   R = R^ Exp(dtheta),  p = p^ + R^ dp,  v = v^ + R^ dv,  ba = ba^ + dba,  bg = bg^ + dbg,
// order [theta, p, v, ba, bg]. NavState rotates dp and dv by the estimate's rotation R^
// (the paper writes R, which agrees to first order); this makes the chart an exact
// product of a right SO(3) perturbation and two body-frame translations.
//
// Against `left` (p + dp_l, Exp(dtheta_l) R, v + dv_l): R^ Exp(dtheta) = Exp(R^ dtheta) R^,
// so dtheta_l = R^ dtheta, dp_l = R^ dp, dv_l = R^ dv exactly; the Jacobians are
// block-diagonal rotations plus a bias permutation.
#include "right_rotation_state.h"

// left's blocks rotated by R^T: p, v body-frame
IMUCONV_RIGHT_ROTATION_STATE(
    "gtsam_navstate", "1.0.0",
    "gtsam::NavState::retract: R Exp(dtheta), p + R dp, v + R dv, b + db; [theta,p,v,ba,bg]",
    (Block::theta, Block::p, Block::v, Block::ba, Block::bg), (Block::theta, Block::p, Block::v))
