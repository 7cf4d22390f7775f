// `gtsam_manifold_jacobian`: the chart GTSAM's ManifoldPreintegration (and the tangent
// preintegration's Jacobians) state their bias Jacobians delRdelBiasOmega, delPdelBiasAcc,
// delPdelBiasOmega, delVdelBiasAcc, delVdelBiasOmega in, the paper's j perturbation
// (eq. subeq:preint-error-dr..subeq:preint-error-db): a right perturbation of the rotation
// and vector-space differences of dp and dv, as GTSAM's BiasCorrectionJacobians tests
// differentiate them, with the bias entry's sign Delta b = Delta b^ - db:
//   Delta R = Delta R^ Exp(dtheta),  dp = dp^ + dp,  dv = dv^ + dv,
//   Delta b_a = Delta b_a^ - dba,  Delta b_g = Delta b_g^ - dbg,
// order [theta, p, v, ba, bg].
//
// Against `preint_reference` it differs only in the bias sign and order: the Jacobians are
// identities on theta, p, v and -I on the swapped bias blocks.
#include "right_perturbed_increment.h"

// GTSAM's order, accelerometer bias first.
// The reference's perturbations with GTSAM's order and bias sign: the Jacobians are the
// permutation with -I on the swapped bias blocks, each its own inverse.
IMUCONV_RIGHT_PERTURBED_INCREMENT(
    "gtsam_manifold_jacobian", "1.0.0",
    "GTSAM preintegration bias-Jacobian chart (paper's j): dR Exp(dtheta), dp + dp, dv "
    "+ dv, Db - db; "
    "[theta,p,v,ba,bg]",
    -1, theta, p, v, ba, bg)
