// `forster` (increment; the paper's f, eq. preint-error-forster): the generic suite and its
// conversions derived by hand.
#include "../convention_suite.h"

IMUCONV_INCREMENT_CONVENTION(forster, "theta p v bg ba", "forster");

TEST(PreintStructure, ForsterIsMinusTheReference) {
  for (const PreintIncrement& x : IncrementKind::Points()) {
    // Every block of eq. preint-error-forster enters with a minus sign, in the reference's
    // order, so the permutation is the identity and the conversion -I.
    EXPECT_TRUE(
        Plugins().conversion("preint_reference", "forster", x).isApprox(-Mat15::Identity(), 0.0));
    EXPECT_TRUE(
        Plugins().conversion("forster", "preint_reference", x).isApprox(-Mat15::Identity(), 0.0));
  }
}

TEST(PreintStructure, ForsterToManifoldJacobianFlipsMotionKeepsBias) {
  // f and j have the same bias sign (Delta b = Delta b^ - db) but opposite motion signs.
  ExpectConversion("forster", "gtsam_manifold_jacobian",
                   [](const PreintIncrement&) -> BlockEntries {
                     return {{"theta", -I3}, {"p", -I3}, {"v", -I3}};
                   });
}
