// `gtsam_manifold` (the paper's c, eq. residual-error): the generic suite and its conversion to
// its bias-Jacobian chart derived by hand.
#include "suite.h"

namespace {

using namespace imuconv::test::increment;

IMUCONV_CONVENTION_SUITE(IncrementConventionSuite, gtsam_manifold);

TEST(PreintStructure, ManifoldToManifoldJacobianRotatesTranslations) {
  for (const PreintIncrement& x : IncrementKind::Points()) {
    // eq. residual-error vs subeq:preint-error-dp: dp_j = dR^ dp_c, dv_j = dR^ dv_c.
    ExpectConversion("gtsam_manifold", "gtsam_manifold_jacobian", x,
                     Expect("gtsam_manifold", "gtsam_manifold_jacobian")
                         .set("theta", "theta", I3)
                         .set("p", "p", x.dR)
                         .set("v", "v", x.dR)
                         .set("ba", "ba", I3)
                         .set("bg", "bg", I3)
                         .matrix());
  }
}

}  // namespace
