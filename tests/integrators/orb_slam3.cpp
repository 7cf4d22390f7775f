// ORB-SLAM3's EdgeInertial Jacobians (imuconv/kernels/orb_slam3.h) against central
// differences of its own residual, through its own increments: ImuCamPose::Update for the
// poses (R <- R Exp(dtheta), t <- t + R dt), additive velocities and biases.
//
// The residual is double in the states, so the pose and velocity columns are differenced
// with h = 1e-6: truncation about h^2, rounding about eps |r| / h with |r| the largest term
// differenced (positions near 450 m: 5e-8), judged relative to entries above 1e-4 of the
// largest, so bounded by 10 times that rounding over the floor (at least 1e-6).
// The biases enter through the float preintegration (b1 is read into float, dR(b1) = dR
// Exp(JRg dbg) in float), so those columns are differenced with h = 1e-3 and judged per 3x3
// block (Frobenius, WorstBlockRelativeDiff): float rounding of dV and dP (6e-8 of 90 m/s and
// 450 m) over 2h is about 1e-5 of a block (tens to hundreds), the truncation of the rotation
// rows about (|JRg| h)^2 = 1e-4. Bound 2e-3.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "imuconv/kernels/orb_slam3.h"
#include "imuconv/so3.h"
#include "imuconv_test.h"
#include "json_quaternion.h"
#include "reference_case.h"
#include "scale_aware.h"

namespace {

using namespace imuconv;
using namespace imuconv::kernels;
using namespace imuconv::test;

struct Edge {
  OrbSlam3Preintegrated pre;
  OrbSlam3Pose<double> s1, s2;
  Vec3 bg1, ba1;
};

Edge MakeEdge(const std::string& id, bool new_bias) {
  const nlohmann::json c = ReadJson(DataPath("reference/cases/" + id + ".json"));
  const ImuNoise noise = CaseNoise(c);
  std::vector<OrbSlam3Step> steps;
  EXPECT_TRUE(OrbSlam3Steps(CaseSamples(c), steps).ok());
  const nlohmann::json& st = c.at("state_s");
  const Vec3 bg = JsonVec3(st.at("bg")), ba = JsonVec3(st.at("ba"));
  Edge e;
  e.pre = PreintegrateOrbSlam3(steps, OrbSlam3CalibFromDensities(noise, 200.0),
                               {bg.cast<float>(), ba.cast<float>()});
  const nlohmann::json& q = st.at("q_wxyz");
  e.s1.R = JsonQuaternionWxyz(q).toRotationMatrix();
  e.s1.p = JsonVec3(st.at("p"));
  e.s1.v = JsonVec3(st.at("v"));
  e.s2 = PredictOrbSlam3(e.pre, e.s1);
  // An end state off the prediction and, for the second point, biases off the
  // linearization point, so that no residual and no bias correction is zero.
  e.s2.R = e.s2.R * so3::Exp(Vec3(0.02, -0.01, 0.03));
  e.s2.p += Vec3(0.3, -0.2, 0.1);
  e.s2.v += Vec3(0.05, 0.04, -0.02);
  e.bg1 = bg + (new_bias ? Vec3(2e-3, -1e-3, 1.5e-3) : Vec3::Zero());
  e.ba1 = ba + (new_bias ? Vec3(-0.01, 0.02, 0.005) : Vec3::Zero());
  return e;
}

class OrbSlam3EdgeDerivatives : public ::testing::TestWithParam<std::tuple<const char*, bool>> {};

TEST_P(OrbSlam3EdgeDerivatives, JacobiansAreTheResidualsDerivatives) {
  const Edge e = MakeEdge(std::get<0>(GetParam()), std::get<1>(GetParam()));
  const OrbSlam3EdgeInertial at = EvaluateOrbSlam3EdgeInertial(e.pre, e.s1, e.bg1, e.ba1, e.s2);
  // Perturbation k of the 24 coordinates [pose1 (dtheta, dt), v1, bg1, ba1, pose2, v2].
  auto residual = [&](int k, double h) {
    OrbSlam3Pose<double> s1 = e.s1, s2 = e.s2;
    Vec3 bg = e.bg1, ba = e.ba1;
    Vec3 d = Vec3::Zero();
    d(k % 3) = h;
    // Block `b` of a pose's [dtheta, dt, v], the same chart for pose 1 and pose 2: rotation
    // R Exp(dtheta), position p + R dt, velocity v + dv.
    auto perturb_pose = [&d](OrbSlam3Pose<double>& s, int b) {
      if (b == 0)
        s.R = s.R * so3::Exp(d);
      else if (b == 1)
        s.p += s.R * d;
      else
        s.v += d;
    };
    const int block = k / 3;
    if (block < 3)
      perturb_pose(s1, block);
    else if (block == 3)
      bg += d;
    else if (block == 4)
      ba += d;
    else
      perturb_pose(s2, block - 5);
    return EvaluateOrbSlam3EdgeInertial(e.pre, s1, bg, ba, s2).residual;
  };
  Eigen::Matrix<double, 9, 24> analytic;
  analytic << at.J_pose1, at.J_vel1, at.J_gyro_bias1, at.J_acc_bias1, at.J_pose2, at.J_vel2;
  Eigen::Matrix<double, 9, 24> numeric;
  for (int k = 0; k < 24; ++k) {
    const double h = (k / 3 == 3 || k / 3 == 4) ? 1e-3 : 1e-6;
    numeric.col(k) = (residual(k, h) - residual(k, -h)) / (2 * h);
  }
  Eigen::Matrix<double, 9, 18> state_num, state_ana;
  state_num << numeric.leftCols<9>(), numeric.rightCols<9>();
  state_ana << analytic.leftCols<9>(), analytic.rightCols<9>();
  const ScaledDiff states = RelativeAboveFloorDiff(state_num, state_ana);
  const ScaledDiff biases =
      WorstBlockRelativeDiff(numeric.middleCols<6>(9), analytic.middleCols<6>(9));
  const double largest = std::max({e.s2.p.cwiseAbs().maxCoeff(), e.s1.p.cwiseAbs().maxCoeff(),
                                   static_cast<double>(e.pre.dP.cwiseAbs().maxCoeff()), 1.0});
  const double rounding = std::numeric_limits<double>::epsilon() * largest / 1e-6;
  const double state_bound =
      std::max(1e-6, 10.0 * rounding / (1e-4 * state_ana.cwiseAbs().maxCoeff()));
  std::printf("  %-13s %s: pose and velocity columns %.2g (bound %.2g), bias blocks %.2g\n",
              std::get<0>(GetParam()), std::get<1>(GetParam()) ? "new bias" : "lin bias", states.d,
              state_bound, biases.d);
  EXPECT_LE(states.d, state_bound) << "at (" << states.row << "," << states.col << ")";
  EXPECT_LE(biases.d, 2e-3) << "block (" << biases.row << "," << biases.col << ")";
}

std::string EdgeName(const ::testing::TestParamInfo<std::tuple<const char*, bool>>& info) {
  std::string name = std::get<0>(info.param);
  for (char& ch : name)
    if (ch == '-') ch = '_';
  return name + (std::get<1>(info.param) ? "_new_bias" : "_lin_bias");
}

INSTANTIATE_TEST_SUITE_P(Reference, OrbSlam3EdgeDerivatives,
                         ::testing::Combine(::testing::ValuesIn(kReferenceCaseIds),
                                            ::testing::Bool()),
                         EdgeName);

}  // namespace
