// `gtsam_manifold_jacobian` (the paper's j, eq. subeq:preint-error-dr..db): the generic suite
// and its conversion from the reference derived by hand.
#include "suite.h"

namespace {

using namespace imuconv::test::increment;

IMUCONV_CONVENTION_SUITE(IncrementConventionSuite, gtsam_manifold_jacobian);

TEST(PreintStructure, ReferenceToManifoldJacobianFlipsAndSwapsBiases) {
  for (const PreintIncrement& x : IncrementKind::Points()) {
    const Mat15 J = Plugins().increment_conversion("preint_reference", "gtsam_manifold_jacobian", x);
    ExpectConversion("preint_reference", "gtsam_manifold_jacobian", x,
                     Expect("preint_reference", "gtsam_manifold_jacobian")
                         .set("theta", "theta", I3)
                         .set("p", "p", I3)
                         .set("v", "v", I3)
                         .set("ba", "ba", -I3)
                         .set("bg", "bg", -I3)
                         .matrix());
    // Raw indices: j's ba rows 9-11 read the reference's ba columns 12-14 with a minus sign.
    EXPECT_TRUE((J.block<3, 3>(9, 12).isApprox(-I3, 0.0)));
    EXPECT_TRUE((J.block<3, 3>(12, 9).isApprox(-I3, 0.0)));
  }
}

}  // namespace
