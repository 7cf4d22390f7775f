// `forster` (increment; the paper's f, eq. preint-error-forster): the generic suite and its
// conversions derived by hand.
#include "suite.h"

namespace {

using namespace imuconv::test::increment;

IMUCONV_CONVENTION_SUITE(IncrementConventionSuite, forster);

TEST(PreintStructure, ForsterIsMinusTheReference) {
  for (const PreintIncrement& x : IncrementKind::Points()) {
    // Every block of eq. preint-error-forster enters with a minus sign, in the reference's
    // order, so the permutation is the identity and the conversion -I.
    EXPECT_TRUE(Plugins().increment_conversion("preint_reference", "forster", x).isApprox(-Mat15::Identity(), 0.0));
    EXPECT_TRUE(Plugins().increment_conversion("forster", "preint_reference", x).isApprox(-Mat15::Identity(), 0.0));
  }
}

TEST(PreintStructure, ForsterToManifoldJacobianFlipsMotionKeepsBias) {
  for (const PreintIncrement& x : IncrementKind::Points()) {
    // f and j have the same bias sign (Delta b = Delta b^ - db) but opposite motion signs.
    ExpectConversion("forster", "gtsam_manifold_jacobian", x,
                     Expect("forster", "gtsam_manifold_jacobian")
                         .set("theta", "theta", -I3)
                         .set("p", "p", -I3)
                         .set("v", "v", -I3)
                         .set("ba", "ba", I3)
                         .set("bg", "bg", I3)
                         .matrix());
  }
}

}  // namespace
