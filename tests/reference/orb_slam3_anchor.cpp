// ORB-SLAM3's own numbers (tests/data/reference/anchors/orb-slam3, README.md there): its
// IMU::Preintegrated fed by Tracking's loop over each of the ten reference cases, its
// tracking prediction, the first-order bias update and Reintegrate, and EdgeInertial's
// information, residual, chi2 and six Jacobians at two biases, against imuconv's ORB-SLAM3
// kernel (imuconv/kernels/orb_slam3.h), which computes in float where the original does.
//
// Tolerances. The original is single precision: float's epsilon is 6e-8, and 2000 steps of
// products of 3x3 and 9x9 float matrices accumulate rounding of about sqrt(2000) to 2000
// epsilons, 3e-6 to 1.2e-4 relative, for the same expressions evaluated in another order.
// The bound is the issue's 1e-4 by the note's metric on every float result and on what the
// double parts compute from them; dT, a float sum of float steps, is also compared bit for
// bit. Measured (GCC 12, x86-64 and, with contraction off as core/CMakeLists.txt sets it, any
// target): every float result equal bit for bit on the ten cases (the kernel evaluates the
// original's expressions in the original's order, including the double cosines of its
// unqualified cos()), the double EdgeInertial results within 4.7e-11 (smooth-3: its
// information's inversion).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "anchor_field_diffs.h"
#include "anchor_members.h"
#include "anchors.h"
#include "imuconv/kernels/orb_slam3.h"
#include "imuconv_test.h"
#include "orb_slam3_float.h"
#include "reference_case.h"
#include "scale_aware.h"

namespace {

using namespace imuconv;
using namespace imuconv::kernels;
using namespace imuconv::test;

OrbSlam3Pose<double> JsonPose(const nlohmann::json& s) {
  OrbSlam3Pose<double> x;
  x.R = JsonMatrix(s.at("R"));
  x.p = JsonVec3(s.at("p"));
  x.v = JsonVec3(s.at("v"));
  return x;
}

OrbSlam3Bias JsonFloatBias(const nlohmann::json& b) {
  return {JsonVec3(b.at("bg")).cast<float>(), JsonVec3(b.at("ba")).cast<float>()};
}

void ExpectPreintegrated(const nlohmann::json& j, const OrbSlam3Preintegrated& p,
                         AnchorFieldDiffs& w) {
  EXPECT_EQ(static_cast<float>(j.at("dT").get<double>()), p.dT);  // the same float additions
  EXPECT_NEAR(j.at("dT").get<double>(), p.dT, 1e-6);
  w.Float("dR", JsonMatrix(j.at("dR")), p.dR.cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("dV", JsonMatrix(j.at("dV")), p.dV.cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("dP", JsonMatrix(j.at("dP")), p.dP.cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("JRg", JsonMatrix(j.at("JRg")), p.JRg.cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("JVg", JsonMatrix(j.at("JVg")), p.JVg.cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("JVa", JsonMatrix(j.at("JVa")), p.JVa.cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("JPg", JsonMatrix(j.at("JPg")), p.JPg.cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("JPa", JsonMatrix(j.at("JPa")), p.JPa.cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("avgA", JsonMatrix(j.at("avgA")), p.avgA.cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("avgW", JsonMatrix(j.at("avgW")), p.avgW.cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("C", JsonMatrix(j.at("C").at("matrix")), p.C.cast<double>(),
          kOrbSlam3SameFloatArithmetic);
}

class OrbSlam3Anchor : public AnchorCaseJsonTest {
 protected:
  OrbSlam3Anchor() : AnchorCaseJsonTest("orb-slam3") {}
  void SetUp() override {
    const ImuNoise noise = CaseNoise(case_);
    ASSERT_EQ(inputs_.at("IMU.NoiseGyro").get<double>(), noise.gyro_noise_density);
    ASSERT_EQ(inputs_.at("IMU.NoiseAcc").get<double>(), noise.accel_noise_density);
    ASSERT_EQ(inputs_.at("IMU.GyroWalk").get<double>(), noise.gyro_random_walk);
    ASSERT_EQ(inputs_.at("IMU.AccWalk").get<double>(), noise.accel_random_walk);
    calib_ = OrbSlam3CalibFromDensities(noise, inputs_.at("IMU.Frequency").get<double>());
    // The Calib ORB-SLAM3 made, bit for bit (the noise interpretation of the header).
    const Eigen::VectorXd cov = JsonMatrix(inputs_.at("calib_Cov_diag")),
                          walk = JsonMatrix(inputs_.at("calib_CovWalk_diag"));
    for (int i = 0; i < 6; ++i) {
      ASSERT_EQ(static_cast<float>(cov(i)), calib_.cov(i)) << i;
      ASSERT_EQ(static_cast<float>(walk(i)), calib_.cov_walk(i)) << i;
    }
    const nlohmann::json& st = case_.at("state_s");
    bias_.bg = JsonVec3(st.at("bg")).cast<float>();
    bias_.ba = JsonVec3(st.at("ba")).cast<float>();
    const OrbSlam3Bias file_bias = JsonFloatBias(inputs_.at("bias_lin_float"));
    ASSERT_EQ(file_bias.bg, bias_.bg);
    ASSERT_EQ(file_bias.ba, bias_.ba);
    const std::vector<ImuSample> samples = CaseSamples(case_);
    ASSERT_EQ(inputs_.at("n_samples").get<std::size_t>(), samples.size());
    ASSERT_TRUE(OrbSlam3Steps(samples, steps_).ok());
    ASSERT_EQ(inputs_.at("n_integrate").get<std::size_t>(), steps_.size());
  }

  OrbSlam3Calib calib_;
  OrbSlam3Bias bias_;
  std::vector<OrbSlam3Step> steps_;
};

TEST_P(OrbSlam3Anchor, PreintegrationAndPredictionAreOrbSlam3Own) {
  const OrbSlam3Preintegrated pre = PreintegrateOrbSlam3(steps_, calib_, bias_);
  AnchorFieldDiffs w(std::string(GetParam()) + " preintegration", kOrbSlam3FloatTol);
  ExpectPreintegrated(anchor_.at("preintegration"), pre, w);

  const nlohmann::json& st = case_.at("state_s");
  const nlohmann::json& q = st.at("q_wxyz");
  OrbSlam3Pose<double> start;
  start.R = JsonQuaternionWxyz(q).toRotationMatrix();
  start.p = JsonVec3(st.at("p"));
  start.v = JsonVec3(st.at("v"));
  OrbSlam3Pose<float> start_float;
  start_float.R = start.R.cast<float>();
  start_float.p = start.p.cast<float>();
  start_float.v = start.v.cast<float>();
  const OrbSlam3Pose<float> tracked = PredictOrbSlam3Tracking(pre, start_float);
  const nlohmann::json& tj = anchor_.at("predict_tracking_float");
  w.Float("tracking R", JsonMatrix(tj.at("R")), tracked.R.cast<double>(),
          kOrbSlam3SameFloatArithmetic);
  w.Float("tracking p", JsonMatrix(tj.at("p")), tracked.p.cast<double>(),
          kOrbSlam3SameFloatArithmetic);
  w.Float("tracking v", JsonMatrix(tj.at("v")), tracked.v.cast<double>(),
          kOrbSlam3SameFloatArithmetic);
  const OrbSlam3Pose<double> predicted = PredictOrbSlam3(pre, start);
  const nlohmann::json& pj = anchor_.at("predict");
  w.Float("predict R", JsonMatrix(pj.at("R")), predicted.R, kOrbSlam3SameFloatArithmetic);
  w.Float("predict p", JsonMatrix(pj.at("p")), predicted.p, kOrbSlam3SameFloatArithmetic);
  w.Float("predict v", JsonMatrix(pj.at("v")), predicted.v, kOrbSlam3SameFloatArithmetic);
  w.Print();
}

TEST_P(OrbSlam3Anchor, BiasUpdateAndReintegrationAreOrbSlam3Own) {
  const OrbSlam3Preintegrated pre = PreintegrateOrbSlam3(steps_, calib_, bias_);
  const nlohmann::json& bc = anchor_.at("bias_correction");
  const OrbSlam3Bias b_new = JsonFloatBias(bc.at("bias_new_float"));
  ASSERT_EQ(b_new.bg, JsonVec3(bc.at("bg_new")).cast<float>());
  ASSERT_EQ(b_new.ba, JsonVec3(bc.at("ba_new")).cast<float>());
  AnchorFieldDiffs w(std::string(GetParam()) + " bias update", kOrbSlam3FloatTol);
  const nlohmann::json& fo = bc.at("first_order");
  Eigen::Matrix<float, 6, 1> db;
  db << b_new.bg - pre.b.bg, b_new.ba - pre.b.ba;
  w.Float("db", JsonMatrix(fo.at("db")), db.cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("first-order dR", JsonMatrix(fo.at("dR")),
          OrbSlam3DeltaRotation(pre, b_new).cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("first-order dV", JsonMatrix(fo.at("dV")),
          OrbSlam3DeltaVelocity(pre, b_new).cast<double>(), kOrbSlam3SameFloatArithmetic);
  w.Float("first-order dP", JsonMatrix(fo.at("dP")),
          OrbSlam3DeltaPosition(pre, b_new).cast<double>(), kOrbSlam3SameFloatArithmetic);
  ExpectPreintegrated(bc.at("reintegrated"), PreintegrateOrbSlam3(pre.steps, calib_, b_new), w);
  w.Print();
}

TEST_P(OrbSlam3Anchor, EdgeInertialIsOrbSlam3Own) {
  if (!kOrbSlam3SameFloatArithmetic) {
    // EdgeInertial computes in double from the float deltas. Where the float rounding is not
    // the original's, those deltas differ by about 1e-5 of their size (the two tests above
    // check that), and the residual, a difference of terms as large as the deltas (|dP| up to
    // 450 m), moves by up to 2.4e-3 of them (measured under qemu on aarch64): there is no
    // original's number to compare it with on this target.
    GTEST_SKIP()
        << "EdgeInertial is compared where the original's float arithmetic is reproduced (x86-64)";
  }
  const OrbSlam3Preintegrated pre = PreintegrateOrbSlam3(steps_, calib_, bias_);
  const nlohmann::json& ej = anchor_.at("edge_inertial");
  EXPECT_EQ(static_cast<float>(ej.at("dt").get<double>()), pre.dT);
  const OrbSlam3Pose<double> s1 = JsonPose(ej.at("state_i")), s2 = JsonPose(ej.at("state_j"));
  AnchorFieldDiffs w(std::string(GetParam()) + " EdgeInertial", kOrbSlam3FloatTol);
  const Mat9 info = OrbSlam3EdgeInformation(pre);
  w.Metric("information", JsonMatrix(ej.at("information")), info);
  struct At {
    const char* key;
    const char* state;
  };
  for (const At at : {At{"at_lin_bias", "state_i"}, At{"at_new_bias", "state_i_new_bias"}}) {
    const nlohmann::json& sj = ej.at(at.state);
    const OrbSlam3EdgeInertial e =
        EvaluateOrbSlam3EdgeInertial(pre, s1, JsonVec3(sj.at("bg")), JsonVec3(sj.at("ba")), s2);
    const nlohmann::json& r = ej.at(at.key);
    w.Metric("residual", JsonMatrix(r.at("residual")), e.residual);
    w.Metric("chi2", Eigen::Matrix<double, 1, 1>(r.at("chi2").get<double>()),
             Eigen::Matrix<double, 1, 1>(e.chi2));
    IMUCONV_CHECK_ANCHOR_MEMBERS(w.Metric, r, e,
                                 (J_pose1)(J_vel1)(J_gyro_bias1)(J_acc_bias1)(J_pose2)(J_vel2));
  }
  w.Print();
}

INSTANTIATE_TEST_SUITE_P(Reference, OrbSlam3Anchor, ::testing::ValuesIn(kReferenceCaseIds),
                         CaseTestName);

}  // namespace
