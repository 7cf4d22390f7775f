// `forster` (state): the generic suite and its conversions derived by hand.
#include "../convention_suite.h"

IMUCONV_STATE_CONVENTION(forster, "theta p v bg ba");

TEST(StateStructure, LeftToForster) {
  // Right rotation and body-frame position (R^T), world velocity, biases in place.
  ExpectConversion("left", "forster", [](const ImuState& x) -> BlockEntries {
    const Mat3 Rt = x.R.transpose();
    return {{"theta", Rt}, {"p", Rt}};
  });
}

TEST(StateStructure, ForsterToNavStateDiffersInVelocityFrame) {
  // Same rotation and position perturbation; Forster's world-frame dv is R^ dv_nav.
  ExpectConversion("forster", "gtsam_navstate", [](const ImuState& x) -> BlockEntries {
    return {{"v", x.R.transpose()}};
  });
}

TEST(StateStructure, ForsterToOpenVinsJplAgreeOnRotation) {
  // Both perturb R on the right; OpenVINS's position is global (R^ dp_forster).
  ExpectConversion("forster", "openvins_jpl", [](const ImuState& x) -> BlockEntries {
    return {{"p", x.R}};
  });
}
