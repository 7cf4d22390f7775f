// `gtsam_tangent`: the generic suite, its conversion to the bias-Jacobian chart (the right
// Jacobian) and the limit of its Log parameterisation.
#include <cmath>

#include "../convention_suite.h"

IMUCONV_INCREMENT_CONVENTION(gtsam_tangent, "theta p v ba bg", "gtsam_tangent");

TEST(PreintStructure, TangentToManifoldJacobianIsTheRightJacobian) {
  // Exp(psi + dtheta) = Exp(psi) Exp(Jr(psi) dtheta + ...), psi = Log(dR^): the tangent
  // perturbation is Jr(psi) dtheta in the right-perturbation chart; dp, dv, Delta b (same
  // sign and order) pass through.
  ExpectConversion("gtsam_tangent", "gtsam_manifold_jacobian",
                   [](const PreintIncrement& x) -> BlockEntries {
                     return {{"theta", so3::Jr(so3::Log(x.dR))}};
                   });
}

// gtsam_tangent parameterises dR by Log(dR) in (-pi, pi]: it is a chart only while
// |Log(dR^) + dtheta| < pi. Near the limit it still inverts; past it Log wraps around.
TEST(PreintStructure, TangentChartHoldsUpToPiAndWrapsBeyond) {
  const auto tangent = Plugins().increment_convention("gtsam_tangent");
  const Vec3 axis = Vec3(0.3, -0.5, 0.8).normalized();
  PreintIncrement x;
  x.dR = so3::Exp(3.0 * axis);
  Vec15 d = Vec15::Zero();
  d.segment<3>(0) = 0.1 * axis;  // |psi + dtheta| = 3.1 < pi
  PreintIncrement y;
  Vec15 back;
  tangent->retract(x, d, y);
  tangent->local(x, y, back);
  // Log near pi loses ~eps / (pi - |phi|) ~ 1e-14: still a tight inverse.
  EXPECT_LE((back - d).cwiseAbs().maxCoeff(), 1e-12);
  d.segment<3>(0) = 0.2 * axis;  // |psi + dtheta| = 3.2 > pi: Log returns the wrapped angle
  tangent->retract(x, d, y);
  tangent->local(x, y, back);
  EXPECT_GT((back - d).norm(), 1.0);  // wrapped: 3.2 axis comes back as (3.2 - 2 pi) axis
}
