// `gtsam_manifold_jacobian` (the paper's j, eq. subeq:preint-error-dr..db): the generic suite
// and its conversion from the reference derived by hand.
#include "../convention_suite.h"

IMUCONV_INCREMENT_CONVENTION(gtsam_manifold_jacobian, "theta p v ba bg", "gtsam_manifold_jacobian");

TEST(PreintStructure, ReferenceToManifoldJacobianFlipsAndSwapsBiases) {
  ExpectConversion("preint_reference", "gtsam_manifold_jacobian",
                   [](const PreintIncrement&) -> BlockEntries {
                     return {{"ba", -I3}, {"bg", -I3}};
                   });
  for (const PreintIncrement& x : IncrementKind::Points()) {
    const Mat15 J = Plugins().conversion("preint_reference", "gtsam_manifold_jacobian", x);
    // Raw indices: j's ba rows 9-11 read the reference's ba columns 12-14 with a minus sign.
    EXPECT_TRUE((J.block<3, 3>(9, 12).isApprox(-I3, 0.0)));
    EXPECT_TRUE((J.block<3, 3>(12, 9).isApprox(-I3, 0.0)));
  }
}
