// `basalt` (increment; Basalt's delta state, left rotation error): the generic suite and its
// conversions derived by hand.
#include "../convention_suite.h"

IMUCONV_INCREMENT_CONVENTION(basalt, "p theta v bg ba", "basalt");

TEST(PreintStructure, BasaltRotatesTheRotationBlockByTheIncrement) {
  // Exp(dtheta) dR^ = dR^ Exp(dR^T dtheta): the reference's rotation error is dR^T times
  // Basalt's; everything else is the reference's, reordered.
  ExpectReferenceWithLeftRotation("basalt");
}

TEST(PreintStructure, BasaltToGtsamManifoldCovarianceChart) {
  // GTSAM's covariance chart c rotates p and v into the increment's frame as well (NavState
  // retract: dp^ + dR^ dp_c) and takes Delta b = Delta b^ - db: from Basalt's left error,
  // dtheta_c = dR^T dtheta, dp_c = dR^T dp, dv_c = dR^T dv, and -I on the biases.
  ExpectConversion("basalt", "gtsam_manifold", [](const PreintIncrement& x) -> BlockEntries {
    const Mat3 Rt = x.dR.transpose();
    return {{"theta", Rt}, {"p", Rt}, {"v", Rt}, {"ba", -I3}, {"bg", -I3}};
  });
}
