// `basalt`: the delta-state perturbation of Basalt's IntegratedImuMeasurement (its 9x9
// covariance and d_state_d_ba, d_state_d_bg; PoseVelState::applyInc), order [p, theta, v]
// ([trans, rot, vel]) followed by the biases in Basalt's state order [bg, ba]:
//   dp = dp^ + dp,  Delta R = Exp(dtheta) Delta R^ (LEFT, in the start frame),  dv = dv^ + dv,
//   Delta b = Delta b^ + db.
// Basalt's delta state has no bias entry; here it is the random walk over the interval that
// Basalt's separate bias factors weight, with the plus sign of a state's bias error. This is
// the state reference chart `left` applied to the increment (LeftReferenceIncrementChart,
// plugin/convention.h), as applyInc is `left` on a state.
//
// Against `preint_reference` (right rotation error): Exp(dtheta) dR^ = dR^ Exp(dR^T dtheta),
// so dtheta_ref = dR^T dtheta and dtheta = dR^ dtheta_ref; the other blocks are a
// permutation.
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

IMUCONV_PLUGIN(IncrementConvention, imuconv::plugin::LeftReferenceIncrementChart, "basalt", "1.0.0",
               "Basalt IntegratedImuMeasurement delta state: dp + dp, Exp(dtheta) dR, dv + dv, Db "
               "+ db; [p,theta,v,bg,ba]")
