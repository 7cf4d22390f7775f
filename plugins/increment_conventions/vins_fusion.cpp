// `vins_fusion`: the error state of VINS-Fusion's IntegrationBase (its jacobian and
// covariance, and IMUFactor's residual), order [p, theta, v, ba, bg] (O_P, O_R, O_V, O_BA,
// O_BG):
//   dp = dp^ + dp,  Delta q = Delta q^ (x) [1, dtheta/2],  dv = dv^ + dv,  Delta b = Delta b^ + db.
// The rotation error sits on the right of the quaternion in the start frame; its chart here
// is the exact Delta R = Delta R^ Exp(dtheta), which agrees with upstream's [1, dtheta/2] to
// first order, all a covariance or a Jacobian sees. The bias entry has the plus sign:
// upstream propagates the bias errors with F's identity blocks and its random-walk noise,
// so its state-bias cross covariances have the sign of d delta / d b (GTSAM's cov15 has the
// opposite one).
//
// Against `preint_reference` (same perturbations, order [theta, p, v, bg, ba]): a
// permutation, both ways.
#include "right_perturbed_increment.h"

IMUCONV_RIGHT_PERTURBED_INCREMENT(
    "vins_fusion", "1.0.0",
    "VINS-Fusion IntegrationBase: dp + dp, dq (x) [1, dtheta/2], dv + dv, Db + db; "
    "[p,theta,v,ba,bg]",
    +1, p, theta, v, ba, bg)
