// `okvis2` (increment; the chart of OKVIS2's P_delta, left rotation error in the frame S0):
// the generic suite and its conversions derived by hand.
#include "../convention_suite.h"

IMUCONV_INCREMENT_CONVENTION(okvis2, "p theta v bg ba", "okvis2");

TEST(PreintStructure, Okvis2RotatesTheRotationBlockByTheIncrement) {
  // Exp(dalpha) Delta_C^ = Delta_C^ Exp(Delta_C^T dalpha): the reference's rotation error is
  // Delta_C^T times OKVIS's; p, v and the biases are the reference's, reordered.
  ExpectReferenceWithLeftRotation("okvis2");
}

TEST(PreintStructure, Okvis2IsBasaltsDeltaState) {
  // Basalt's delta state perturbs every block as OKVIS does, in the same order
  // [p, theta, v, bg, ba], with the same plus sign on the bias walk: the identity.
  ExpectConversion("okvis2", "basalt", [](const PreintIncrement&) -> BlockEntries { return {}; });
}

TEST(PreintStructure, Okvis2ToGtsamManifoldCovarianceChart) {
  // GTSAM's covariance chart c rotates p and v into the increment's frame as well and takes
  // Delta b = Delta b^ - db: dalpha_c = Delta_C^T dalpha, dp_c = Delta_C^T dp,
  // dv_c = Delta_C^T dv, and -I on the biases.
  ExpectConversion("okvis2", "gtsam_manifold", [](const PreintIncrement& x) -> BlockEntries {
    const Mat3 Rt = x.dR.transpose();
    return {{"theta", Rt}, {"p", Rt}, {"v", Rt}, {"ba", -I3}, {"bg", -I3}};
  });
}
