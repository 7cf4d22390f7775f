// `orb_slam3` (increment; ORB-SLAM3's IMU::Preintegrated error state): the generic suite and
// its conversions derived by hand.
#include "../convention_suite.h"

IMUCONV_INCREMENT_CONVENTION(orb_slam3, "theta v p bg ba", "orb_slam3");

TEST(PreintStructure, OrbSlam3IsTheReferenceReordered) {
  // The same perturbation of every block as preint_reference (right rotation error, plus
  // signs throughout), in the order [theta, v, p, bg, ba]: a pure permutation.
  ExpectReferenceReordered("orb_slam3");
}

TEST(PreintStructure, OrbSlam3ToBasaltRotatesOnlyTheRotationBlock) {
  // dR^ Exp(dtheta) = Exp(dR^ dtheta) dR^: Basalt's left rotation error is dR^ times ORB's;
  // dv, dp and the biases are the same numbers in another order.
  ExpectConversion("orb_slam3", "basalt", [](const PreintIncrement& x) -> BlockEntries {
    return {{"theta", x.dR}};
  });
}

TEST(PreintStructure, OrbSlam3ToManifoldJacobianFlipsOnlyTheBias) {
  // GTSAM's j chart perturbs the motion the same way but takes Delta b = Delta b^ - db.
  ExpectConversion("orb_slam3", "gtsam_manifold_jacobian",
                   [](const PreintIncrement&) -> BlockEntries {
                     return {{"ba", -I3}, {"bg", -I3}};
                   });
}
