// `gtsam_manifold_jacobian` (the paper's j, eq. subeq:preint-error-dr..db): the generic suite
// and its conversion from the reference derived by hand.
#include "../convention_suite.h"

IMUCONV_CONVENTION_SUITE(IncrementConventionSuite, gtsam_manifold_jacobian);
IMUCONV_CONVENTION_BLOCK_ORDER(IncrementKind, gtsam_manifold_jacobian, "theta p v ba bg");
IMUCONV_BIAS_JACOBIAN_CHART(gtsam_manifold_jacobian, "gtsam_manifold_jacobian");

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
