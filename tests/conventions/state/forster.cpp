// `forster` (state): the generic suite and its conversions derived by hand.
#include "suite.h"

namespace {

using namespace imuconv::test::state;

IMUCONV_CONVENTION_SUITE(StateConventionSuite, forster);

TEST(StateStructure, LeftToForster) {
  for (const ImuState& x : StateKind::Points()) {
    const Mat3 Rt = x.R.transpose();
    // Right rotation and body-frame position (R^T), world velocity, biases in place.
    ExpectConversion("left", "forster", x,
                     Expect("left", "forster")
                         .set("theta", "theta", Rt)
                         .set("p", "p", Rt)
                         .set("v", "v", I3)
                         .set("bg", "bg", I3)
                         .set("ba", "ba", I3)
                         .matrix());
  }
}

TEST(StateStructure, ForsterToNavStateDiffersInVelocityFrame) {
  for (const ImuState& x : StateKind::Points()) {
    // Same rotation and position perturbation; Forster's world-frame dv is R^ dv_nav.
    ExpectConversion("forster", "gtsam_navstate", x,
                     Expect("forster", "gtsam_navstate")
                         .set("theta", "theta", I3)
                         .set("p", "p", I3)
                         .set("v", "v", x.R.transpose())
                         .set("ba", "ba", I3)
                         .set("bg", "bg", I3)
                         .matrix());
  }
}

TEST(StateStructure, ForsterToOpenVinsJplAgreeOnRotation) {
  for (const ImuState& x : StateKind::Points()) {
    // Both perturb R on the right; OpenVINS's position is global (R^ dp_forster).
    ExpectConversion("forster", "openvins_jpl", x,
                     Expect("forster", "openvins_jpl")
                         .set("theta", "theta", I3)
                         .set("p", "p", x.R)
                         .set("v", "v", I3)
                         .set("bg", "bg", I3)
                         .set("ba", "ba", I3)
                         .matrix());
  }
}

}  // namespace
