// `orb_slam3`: the error state of ORB-SLAM3's IMU::Preintegrated (its 15x15 C, and the bias
// Jacobians JRg, JVg, JVa, JPg, JPa), order [theta, v, p, bg, ba]:
//   dR = dR^ Exp(dtheta) (right, in the frame of the interval's first sample),
//   dV = dV^ + dv,  dP = dP^ + dp,  Delta b = Delta b^ + db.
// C's bias blocks are the random walk summed over the steps with the plus sign of a state's
// bias error (ORB-SLAM3 never forms the state-bias cross blocks). The bias Jacobian is in this
// same chart: its rows are d(dtheta, dv, dp)/d(bg, ba) with dR(b) = dR Exp(JRg dbg), dV(b) =
// dV + JVg dbg + JVa dba, dP(b) = dP + JPg dbg + JPa dba (IMU::Preintegrated::GetDelta*), so
// the rows [theta; v; p] and columns [bg, ba] are [[JRg, 0], [JVg, JVa], [JPg, JPa]].
//
// Against `preint_reference` (the same perturbations, order [theta, p, v, bg, ba]): a
// permutation, both ways.
#include "right_perturbed_increment.h"

IMUCONV_RIGHT_PERTURBED_INCREMENT(
    "orb_slam3", "1.0.0",
    "ORB-SLAM3 IMU::Preintegrated: dR Exp(dtheta), dV + dv, dP + dp, Db + db; "
    "[theta,v,p,bg,ba]",
    +1, theta, v, p, bg, ba)
