// `okvis2` (state; OKVIS2's ImuError/PoseManifold error state): the generic suite, its
// conversions derived by hand, and its retract against OKVIS's own update carried out
// literally on a Hamilton quaternion (PoseManifold::plus: q <- deltaQ(dalpha) (x) q,
// deltaQ(phi) = [cos(|phi|/2), sin(|phi|/2) phi/|phi|]).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "../convention_suite.h"

namespace {

IMUCONV_STATE_CONVENTION(okvis2, "p theta v bg ba");

TEST(StateStructure, Okvis2IsLeft) {
  // The same perturbation of each block as `left`, in the same order [r, alpha, v, bg, ba] =
  // [p, theta, v, bg, ba]: the identity both ways.
  ExpectConversion("left", "okvis2", [](const ImuState&) -> BlockEntries { return {}; });
  ExpectConversion("okvis2", "left", [](const ImuState&) -> BlockEntries { return {}; });
}

TEST(StateStructure, Okvis2ToOpenVinsJpl) {
  // OpenVINS's error is R = R^ Exp(theta) (JPL left update of R_GtoI): Exp(alpha) R^ =
  // R^ Exp(R^T alpha), so theta = R^T alpha; p and v are world additive in both.
  ExpectConversion("okvis2", "openvins_jpl", [](const ImuState& x) -> BlockEntries {
    return {{"theta", x.R.transpose()}};
  });
}

/// OKVIS's deltaQ: the unit quaternion of the rotation vector phi.
Eigen::Quaterniond DeltaQ(const Vec3& phi) {
  const double angle = phi.norm();
  if (angle == 0.0) return Eigen::Quaterniond::Identity();
  const Vec3 axis = phi / angle;
  return Eigen::Quaterniond(std::cos(0.5 * angle), std::sin(0.5 * angle) * axis.x(),
                            std::sin(0.5 * angle) * axis.y(), std::sin(0.5 * angle) * axis.z());
}

TEST(Okvis2State, RetractIsPoseManifoldPlus) {
  const auto conv = Plugins().state_convention("okvis2");
  for (int k = 0; k < 4; ++k) {
    ImuState x;
    Eigen::Vector4d c;
    c << imuconv::test::RandVec(1.0), imuconv::test::RandVec(1.0).x();
    const Eigen::Quaterniond q_WS = Eigen::Quaterniond(c[3], c[0], c[1], c[2]).normalized();
    x.R = q_WS.toRotationMatrix();
    x.p = imuconv::test::RandVec(10.0);
    x.v = imuconv::test::RandVec(2.0);
    x.bg = imuconv::test::RandVec(0.01);
    x.ba = imuconv::test::RandVec(0.1);
    for (double s : {1e-8, 1e-3, 0.5, 2.0}) {
      const Vec15 d = s * imuconv::test::RandVec15(1.0);
      ImuState y;
      conv->retract(x, d, y);
      const Mat3 expected_R = (DeltaQ(d.segment<3>(3)) * q_WS).toRotationMatrix();
      // Two routes to one rotation (Rodrigues' matrix times R against a quaternion product):
      // products of unit-size entries, a few ulps.
      EXPECT_LE((y.R - expected_R).cwiseAbs().maxCoeff(), 1e-14) << "|dalpha| " << s;
      EXPECT_EQ(y.p, x.p + d.segment<3>(0));
      EXPECT_EQ(y.v, x.v + d.segment<3>(6));
      EXPECT_EQ(y.bg, x.bg + d.segment<3>(9));
      EXPECT_EQ(y.ba, x.ba + d.segment<3>(12));
    }
  }
}

}  // namespace
