// `vins_fusion` (increment; VINS-Fusion's IntegrationBase error state): the generic suite and
// its conversions derived by hand.
#include "../convention_suite.h"

IMUCONV_INCREMENT_CONVENTION(vins_fusion, "p theta v ba bg", "vins_fusion");

TEST(PreintStructure, VinsFusionIsTheReferenceReordered) {
  // The same perturbation of every block as preint_reference (right rotation error, plus
  // signs throughout), in the order [p, theta, v, ba, bg]: a pure permutation.
  ExpectReferenceReordered("vins_fusion");
}

TEST(PreintStructure, VinsFusionToManifoldJacobianFlipsOnlyTheBias) {
  // GTSAM's j chart perturbs the motion the same way but takes Delta b = Delta b^ - db.
  ExpectConversion("vins_fusion", "gtsam_manifold_jacobian",
                   [](const PreintIncrement&) -> BlockEntries {
                     return {{"ba", -I3}, {"bg", -I3}};
                   });
}
