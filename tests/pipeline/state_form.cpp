// The state form's rotation: the Hamilton body-to-world q_wxyz imuconv writes, or OpenVINS's
// JPL q_GtoI_xyzw, checked against the JPL rotation matrix built from its own definition.
#include <gtest/gtest.h>

#include "imuconv/pipeline/json_io.h"
#include "imuconv/so3.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using nlohmann::json;

/// Reads `j` as a state; the checker's messages, or "" and the state.
std::pair<std::string, ImuState> Read(const json& j) {
  Checker c("state.json");
  const auto x = StateFromJson(Node(j, "", c));
  try {
    c.throw_if_errors();
  } catch (const ConfigError& e) {
    return {e.what(), ImuState{}};
  }
  return {"", *x};
}

// JPL (Trawny & Roumeliotis, "Indirect Kalman Filter for 3D Attitude Estimation", eq. 78):
// C(q) = (2 q4^2 - 1) I - 2 q4 [q]x + 2 q q^T rotates global vectors into the frame, so for
// OpenVINS's q_GtoI it is R_GtoI, and the body-to-world rotation is its transpose.
Mat3 JplGtoI(const Eigen::Vector4d& xyzw) {
  const Vec3 qv = xyzw.head<3>();
  const double q4 = xyzw[3];
  return (2 * q4 * q4 - 1) * Mat3::Identity() - 2 * q4 * so3::skew(qv) + 2 * qv * qv.transpose();
}

TEST(StateForm, OpenVinsJplQuaternionGivesTheBodyToWorldRotation) {
  for (int i = 0; i < 20; ++i) {
    Vec3 w = test::RandVec(1.5);
    if (w.norm() > 2.5) w *= 2.5 / w.norm();  // below 180 degrees: q4 = cos(angle/2) >= 0.31
    const Mat3 R = so3::Exp(w);
    // A JPL q_GtoI for R: any unit quaternion whose C(q) is R^T; found here by a solver of
    // its own (the Hamilton conversion is what is under test): Shepperd on R^T's JPL form.
    const Mat3 C = R.transpose();
    Eigen::Vector4d q;
    q[3] = 0.5 * std::sqrt(std::max(0.0, 1.0 + C.trace()));
    ASSERT_GT(q[3], 0.1) << "a draw too near 180 degrees for this simple solver";
    // C - C^T = -4 q4 [q]x.
    q[0] = (C(1, 2) - C(2, 1)) / (4 * q[3]);
    q[1] = (C(2, 0) - C(0, 2)) / (4 * q[3]);
    q[2] = (C(0, 1) - C(1, 0)) / (4 * q[3]);
    ASSERT_LT((JplGtoI(q) - C).cwiseAbs().maxCoeff(), 1e-14);  // the solver is right
    const auto [error, x] =
        Read({{"p", {1, 2, 3}}, {"q_GtoI_xyzw", {q[0], q[1], q[2], q[3]}}, {"v", {0, 0, 0}}});
    ASSERT_EQ(error, "");
    // Both are a few products of the same numbers: a few ulps of 1.
    EXPECT_LT((x.R - R).cwiseAbs().maxCoeff(), 1e-14);
  }
}

TEST(StateForm, OneRotationExactlyAndAUnitOne) {
  const json p = {1, 2, 3}, v = {0, 0, 0};
  auto [error, x] =
      Read({{"p", p}, {"q_wxyz", {1, 0, 0, 0}}, {"q_GtoI_xyzw", {0, 0, 0, 1}}, {"v", v}});
  EXPECT_EQ(error, "state.json: /q_GtoI_xyzw: give either q_wxyz or q_GtoI_xyzw, not both");
  std::tie(error, x) = Read({{"p", p}, {"v", v}});
  EXPECT_EQ(error,
            "state.json: /q_wxyz: required key is missing (the body-to-world Hamilton q_wxyz, or "
            "OpenVINS's JPL q_GtoI_xyzw)");
  std::tie(error, x) = Read({{"p", p}, {"q_GtoI_xyzw", {0, 0, 0, 2}}, {"v", v}});
  EXPECT_EQ(error.rfind("state.json: /q_GtoI_xyzw: expected a unit quaternion [x, y, z, w] (norm "
                        "within 1e-6 of 1)",
                        0),
            0u)
      << error;
}

}  // namespace
