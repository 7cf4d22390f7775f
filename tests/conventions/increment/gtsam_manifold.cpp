// `gtsam_manifold` (the paper's c, eq. residual-error): the generic suite and its conversion to
// its bias-Jacobian chart derived by hand.
#include "../convention_suite.h"

// GTSAM's ManifoldPreintegration states its covariance in c (gtsam_manifold) and its bias
// Jacobians in j (gtsam_manifold_jacobian); the other conventions each use their own.
IMUCONV_INCREMENT_CONVENTION(gtsam_manifold, "theta p v ba bg", "gtsam_manifold_jacobian");

TEST(PreintStructure, ManifoldToManifoldJacobianRotatesTranslations) {
  // eq. residual-error vs subeq:preint-error-dp: dp_j = dR^ dp_c, dv_j = dR^ dv_c.
  ExpectConversion("gtsam_manifold", "gtsam_manifold_jacobian",
                   [](const PreintIncrement& x) -> BlockEntries {
                     return {{"p", x.dR}, {"v", x.dR}};
                   });
}
