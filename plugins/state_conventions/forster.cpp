// `forster`: the state perturbation of Forster, Carlone, Dellaert and Scaramuzza,
// "On-Manifold Preintegration for Real-Time Visual-Inertial Odometry", IEEE TRO 2017 (the
// retraction of the navigation state its IMU factor is linearised in), as quoted at the end
// of the paper's "Forster Preintegration" paragraph (after eq. forster-res-jac):
//   R = R^ Exp(dtheta),  p = p^ + R^ dp,  v = v^ + dv,  b = b^ + db,
// order [theta, p, v, bg, ba]. The position is perturbed in the body frame of the estimate
// R^ (the paper writes R, equal to first order), the velocity in the world frame.
//
// Against `left`: dtheta_l = R^ dtheta and dp_l = R^ dp exactly, dv_l = dv.
#include "right_rotation_state.h"

// left's blocks rotated by R^T: p body-frame, v not
IMUCONV_RIGHT_ROTATION_STATE(
    "forster", "1.0.0",
    "Forster et al. TRO 2017: R Exp(dtheta), p + R dp, v + dv, b + db; [theta,p,v,bg,ba]",
    (Block::theta, Block::p, Block::v, Block::bg, Block::ba), (Block::theta, Block::p))
