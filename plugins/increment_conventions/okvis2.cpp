// `okvis2`: the perturbation of OKVIS2's preintegrated increment, in which ImuError holds
// P_delta (okvis_ceres ImuError.cpp, redoPreintegration), order [p, alpha, v, bg, ba], all in
// the frame S0 of the interval's first state:
//   Delta_p = Delta_p^ + dp,  Delta_C = Exp(dalpha) Delta_C^ (LEFT, in S0),
//   Delta_v = Delta_v^ + dv,  Delta b = Delta b^ + db.
// Delta_p and Delta_v are acc_doubleintegral and acc_integral, Delta_C the rotation of
// Delta_q; the bias blocks are the random walk over the interval (P_delta's bg, ba blocks
// accumulate sigma_w^2 dt). The bias Jacobians follow from ImuError's first-order correction,
// Dq = exp(-dalpha_db_g dbg) (x) Delta_q, Delta_p + dp_db_g dbg - C_doubleintegral dba,
// Delta_v + dv_db_g dbg - C_integral dba: in this chart d alpha/d bg = -dalpha_db_g.
//
// Against `preint_reference` (Delta R^ Exp(dtheta), order [theta, p, v, bg, ba]):
// Exp(dalpha) Delta_C^ = Delta_C^ Exp(Delta_C^T dalpha), so dtheta = Delta_C^T dalpha and
// dalpha = Delta_C dtheta; the other blocks are the same additive errors, reordered. This is
// the perturbation of `basalt` (Basalt's delta state) in the same order; the two charts are
// one (LeftReferenceIncrementChart, plugin/convention.h), named after each system.
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

IMUCONV_PLUGIN(IncrementConvention, imuconv::plugin::LeftReferenceIncrementChart, "okvis2", "1.0.0",
               "OKVIS2 ImuError P_delta (frame S0): dp + dp, Exp(dalpha) dR, dv + dv, Db + db; "
               "[p,alpha,v,bg,ba]")
