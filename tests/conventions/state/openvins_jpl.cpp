// `openvins_jpl`: the generic suite, its conversion from `left` derived by hand, and the chart
// against an independent JPL quaternion implementation (Trawny and
// Roumeliotis, "Indirect Kalman Filter for 3D Attitude Estimation", 2005, the convention
// OpenVINS follows): q = [q_v; q_4] with the vector part first, the JPL product and
// C(q) = R_GtoI. The plugin's retract is written in body-to-world Hamilton terms
// (R = R^ Exp(phi), phi = 2 atan(|dtheta|/2) dtheta/|dtheta|); here the update is carried
// out literally as OpenVINS's JPLQuat::update does it, q = normalize([dtheta/2; 1]) (x) q^.
#include <gtest/gtest.h>

#include <cmath>

#include "../convention_suite.h"
#include "imuconv/so3.h"

namespace {

using Quat = Eigen::Vector4d;  // JPL: [x, y, z, w], vector part first

// JPL product (Trawny & Roumeliotis eq. 8): q (x) p = [q4 p + p4 q - q x p; q4 p4 - q . p].
Quat JplProduct(const Quat& q, const Quat& p) {
  const Vec3 qv = q.head<3>(), pv = p.head<3>();
  Quat r;
  r.head<3>() = q[3] * pv + p[3] * qv - qv.cross(pv);
  r[3] = q[3] * p[3] - qv.dot(pv);
  return r;
}

// C(q) (eq. 78): (2 q4^2 - 1) I - 2 q4 [q]x + 2 q q^T; for OpenVINS's q_GtoI this is R_GtoI.
Mat3 JplToRot(const Quat& q) {
  const Vec3 qv = q.head<3>();
  Mat3 Sx;
  Sx << 0, -qv.z(), qv.y(), qv.z(), 0, -qv.x(), -qv.y(), qv.x(), 0;
  return (2.0 * q[3] * q[3] - 1.0) * Mat3::Identity() - 2.0 * q[3] * Sx + 2.0 * qv * qv.transpose();
}

// OpenVINS's JPLQuat::update: dq = [dtheta/2; 1] normalised, q = dq (x) q^.
Quat JplUpdate(const Quat& q, const Vec3& dtheta) {
  Quat dq;
  dq << 0.5 * dtheta, 1.0;
  return JplProduct(dq.normalized(), q);
}

Quat RandomJpl() {
  Quat q;
  q << imuconv::test::RandVec(1.0), imuconv::test::RandVec(1.0).x();
  return q.normalized();
}

// 3x3 products of unit-size entries along two different routes: a few ulps.
constexpr double kRotTol = 1e-14;

IMUCONV_STATE_CONVENTION(openvins_jpl, "theta p v bg ba");

TEST(StateStructure, LeftToOpenVinsJpl) {
  // JPL's left update of q_GtoI is a right update of R = R_GtoI^T (R^T dtheta_l to first
  // order: 2 atan(s/2)/s = 1 + O(s^2)); p and v are global-frame additive like left's.
  ExpectConversion("left", "openvins_jpl", [](const ImuState& x) -> BlockEntries {
    return {{"theta", x.R.transpose()}};
  });
}

TEST(OpenVinsJpl, IndependentJplImplementationIsConsistent) {
  // The product is the one whose matrices compose in the same order, C(q (x) p) = C(q) C(p),
  // and C is a rotation.
  for (int k = 0; k < 5; ++k) {
    const Quat q = RandomJpl(), p = RandomJpl();
    EXPECT_LE((JplToRot(JplProduct(q, p)) - JplToRot(q) * JplToRot(p)).cwiseAbs().maxCoeff(),
              kRotTol);
    EXPECT_LE((JplToRot(q) * JplToRot(q).transpose() - Mat3::Identity()).cwiseAbs().maxCoeff(),
              kRotTol);
    EXPECT_NEAR(JplToRot(q).determinant(), 1.0, kRotTol);
  }
  // OpenVINS's error-state definition: R_GtoI = (I - [dtheta]x) R^_GtoI to first order.
  // The second-order remainder is below |dtheta|^2 ~ 2e-14 for |dtheta| = 1.3e-7.
  const Vec3 small(1e-7, -0.5e-7, 0.7e-7);
  const Quat q = RandomJpl();
  EXPECT_LE(
      (JplToRot(JplUpdate(q, small)) - (Mat3::Identity() - imuconv::so3::skew(small)) * JplToRot(q))
          .cwiseAbs()
          .maxCoeff(),
      1e-13);
}

TEST(OpenVinsJpl, RetractIsJplLeftUpdateOfGlobalToImu) {
  const auto conv = Plugins().state_convention("openvins_jpl");
  double worst = 0.0;
  for (int k = 0; k < 4; ++k) {
    const Quat q_GtoI = RandomJpl();
    ImuState x;
    x.R = JplToRot(q_GtoI).transpose();  // body-to-world = R_GtoI^T
    x.p = imuconv::test::RandVec(10.0);
    x.v = imuconv::test::RandVec(2.0);
    x.bg = imuconv::test::RandVec(0.01);
    x.ba = imuconv::test::RandVec(0.1);
    for (double s : {1e-8, 1e-3, 0.5, 2.0, 50.0}) {
      const Vec15 d = s * imuconv::test::RandVec15(1.0);
      const Vec3 dtheta = d.segment<3>(0);
      ImuState y;
      conv->retract(x, d, y);
      const Mat3 expected_R = JplToRot(JplUpdate(q_GtoI, dtheta)).transpose();
      const double err = (y.R - expected_R).cwiseAbs().maxCoeff();
      worst = std::max(worst, err);
      EXPECT_LE(err, kRotTol) << "|dtheta| = " << dtheta.norm();
      // p_IinG, v_IinG and the biases are plain vector additions, order [theta, p, v, bg, ba].
      EXPECT_EQ(y.p, x.p + d.segment<3>(3));
      EXPECT_EQ(y.v, x.v + d.segment<3>(6));
      EXPECT_EQ(y.bg, x.bg + d.segment<3>(9));
      EXPECT_EQ(y.ba, x.ba + d.segment<3>(12));
    }
  }
  std::printf("[ worst    ] openvins_jpl retract vs JPL update          %.3e\n", worst);
}

TEST(OpenVinsJpl, LocalRecoversTheJplErrorAngle) {
  const auto conv = Plugins().state_convention("openvins_jpl");
  const Quat q_GtoI = RandomJpl();
  ImuState x;
  x.R = JplToRot(q_GtoI).transpose();
  for (double s : {1e-8, 1e-3, 0.5, 2.0}) {
    const Vec3 dtheta = s * imuconv::test::RandVec(1.0);
    ImuState y = x;
    y.R = JplToRot(JplUpdate(q_GtoI, dtheta)).transpose();
    Vec15 d;
    conv->local(x, y, d);
    // Relative to max(1, |dtheta|): Log of a product of rotations, then the tan(|phi|/2)
    // rescaling whose derivative at |dtheta| = 2*sqrt(3) is ~7; rounding ~1e-15.
    EXPECT_LE((d.segment<3>(0) - dtheta).cwiseAbs().maxCoeff() / std::max(1.0, dtheta.norm()),
              1e-12)
        << "|dtheta| = " << dtheta.norm();
  }
}

TEST(OpenVinsJpl, HamiltonAngleOfTheJplErrorQuaternion) {
  // The header's closed form: C(dq)^T = Exp(phi), phi = 2 atan(|dtheta|/2) dtheta/|dtheta|.
  for (double s : {1e-6, 0.3, 4.0}) {
    const Vec3 dtheta = s * Vec3(0.3, -0.5, 0.8).normalized();
    Quat identity(0, 0, 0, 1);
    const Mat3 C = JplToRot(JplUpdate(identity, dtheta));
    const Vec3 phi = 2.0 * std::atan(0.5 * s) * dtheta / s;
    EXPECT_LE((C.transpose() - imuconv::so3::Exp(phi)).cwiseAbs().maxCoeff(), kRotTol)
        << "|dtheta| = " << s;
  }
}

}  // namespace
