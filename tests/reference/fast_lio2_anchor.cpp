// FAST-LIO2's own numbers (tests/data/reference/anchors/fast-lio2, README.md there): the
// forward propagation of one scan as ImuProcess drives IKFoM's esekf::predict, on each of the
// ten reference cases, for both runs of each file (`as_fastlio`: gravity on FAST-LIO's S2 of
// length 9.809; `case_gravity`: the case's gravity), against imuconv's FAST-LIO2 kernel
// (imuconv/kernels/fast_lio2.h) in IKFoM's 23-dimensional error state.
//
// Every row and column of the 23x23 covariance, Phi_summed and Qd_summed is compared: the
// pos, rot, vel, bg, ba blocks the issue asks for, and the extrinsic (offset_R_L_I,
// offset_T_L_I) and gravity (S2, two-dimensional) blocks as well.
//
// Tolerances: anchors.h (1e-8 by the note's metric; covariances also on the correlation scale
// and transitions relative to entries above 1e-4 of the largest, at 1e-9). The same formulas
// are evaluated in another order (the noise as one product, MTK's series for sin and cos
// replaced by the library's functions, FMA here, none upstream).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "anchor_field_diffs.h"
#include "anchors.h"
#include "anchors/fast_lio2_start.h"
#include "imuconv/kernels/fast_lio2.h"
#include "imuconv_test.h"
#include "reference_case.h"
#include "scale_aware.h"

namespace {

using namespace imuconv;
using namespace imuconv::kernels;
using namespace imuconv::test;  // DataPath, JsonMatrix, MaxEntryDiff, the anchors' bounds

class FastLio2Anchor : public AnchorCaseJsonTest {
 protected:
  FastLio2Anchor() : AnchorCaseJsonTest("fast-lio2") {}
  void SetUp() override {
    samples_ = CaseSamples(case_);
    ASSERT_EQ(inputs_.at("n_samples").get<std::size_t>(), samples_.size());

    // The noise: each density sigma as the per-sample variance sigma^2 * rate (README); the
    // file's numbers were formed in another order, so equal to a few ulp (1e-15 relative).
    const double rate = inputs_.at("imu_rate").get<double>();
    const nlohmann::json& noise = case_.at("noise");
    auto per_sample = [&](const char* density) {
      const double sigma = noise.at(density).get<double>();
      return sigma * sigma * rate;
    };
    params_.gyr_cov = inputs_.at("gyr_cov").get<double>();
    params_.acc_cov = inputs_.at("acc_cov").get<double>();
    params_.b_gyr_cov = inputs_.at("b_gyr_cov").get<double>();
    params_.b_acc_cov = inputs_.at("b_acc_cov").get<double>();
    EXPECT_NEAR(params_.gyr_cov, per_sample("gyro_noise_density"), 1e-15 * params_.gyr_cov);
    EXPECT_NEAR(params_.acc_cov, per_sample("accel_noise_density"), 1e-15 * params_.acc_cov);
    EXPECT_NEAR(params_.b_gyr_cov, per_sample("gyro_random_walk"), 1e-15 * params_.b_gyr_cov);
    EXPECT_NEAR(params_.b_acc_cov, per_sample("accel_random_walk"), 1e-15 * params_.b_acc_cov);
    params_.G_m_s2 = inputs_.at("G_m_s2").get<double>();
    params_.mean_acc_norm = inputs_.at("mean_acc_norm").get<double>();
    ASSERT_EQ(params_.G_m_s2, 9.81);  // common_lib.h's G_m_s2
    ASSERT_EQ(params_.mean_acc_norm, 9.81);

    // One scan: the previous one ended on the first sample, this one on the last.
    last_scan_end_ = inputs_.at("last_lidar_end_time").get<double>();
    scan_end_ = inputs_.at("lidar_end_time").get<double>();
    ASSERT_EQ(last_scan_end_, samples_.front().t);
    ASSERT_EQ(scan_end_, samples_.back().t);

    // The start state is the case's state_s (SO3's constructor normalizes the quaternion),
    // extrinsics the identity, gravity S2(case gravity), rescaled to 9.809.
    const nlohmann::json& st = case_.at("state_s");
    const nlohmann::json& si = inputs_.at("state_init");
    start_.pos = JsonVec3(st.at("p"));
    start_.rot = JsonQuaternionWxyz(st.at("q_wxyz")).normalized();
    start_.vel = JsonVec3(st.at("v"));
    start_.bg = JsonVec3(st.at("bg"));
    start_.ba = JsonVec3(st.at("ba"));
    gravity_ = JsonVec3(case_.at("gravity"));
    start_.grav = FastLio2GravityAsBuilt(gravity_);
    EXPECT_EQ(JsonVec3(si.at("pos")), start_.pos);
    EXPECT_EQ(JsonVec3(si.at("vel")), start_.vel);
    EXPECT_EQ(JsonVec3(si.at("bg")), start_.bg);
    EXPECT_EQ(JsonVec3(si.at("ba")), start_.ba);
    EXPECT_LE(MaxEntryDiff(JsonMatrix(si.at("rot_q_wxyz")), Wxyz(start_.rot)), 1e-15);
    EXPECT_EQ(Wxyz(JsonQuaternionWxyz(si.at("offset_R_L_I_q_wxyz"))), Eigen::Vector4d(1, 0, 0, 0));
    EXPECT_EQ(JsonVec3(si.at("offset_T_L_I")), Vec3::Zero());
    EXPECT_EQ(JsonVec3(si.at("grav")), start_.grav.vec);
    EXPECT_EQ(si.at("grav_S2_length").get<double>(), start_.grav.length);

    // P0: the case's cov_s_left ([dp, dtheta, dv, dbg, dba], R = Exp(dtheta) R^) in this error
    // state (drot = R^T dtheta), extrinsic and gravity blocks zero. One similarity transform
    // apart from the file's: rounding only, 1e-14 on the correlation scale.
    P0_ = JsonMatrix(inputs_.at("P0").at("matrix"));
    const Mat15 cov_left = JsonMatrix(case_.at("cov_s_left").at("matrix"));
    const Mat23 mapped = refcase::FastLio2StartCovariance(start_.rot, cov_left);
    EXPECT_LE(CorrelationScaleDiff(P0_, mapped).d, 1e-14);
  }

  /// One run of the file against the kernel's propagation with the gravity `grav`.
  void ExpectRun(const char* run, const FastLio2Gravity& grav) {
    const nlohmann::json& j = anchor_.at(run);
    FastLio2State start = start_;
    start.grav = grav;
    FastLio2Propagation out;
    ASSERT_TRUE(
        PropagateFastLio2Scan(samples_, params_, last_scan_end_, scan_end_, start, P0_, out).ok());
    EXPECT_EQ(out.n_predict, j.at("n_predict").get<int>());
    // 2000 additions of dt near 5e-3 in another order: within 2000 eps of 10 s.
    EXPECT_NEAR(out.sum_dt, j.at("sum_dt").get<double>(), 1e-11);
    EXPECT_EQ(out.last_predict_dt, j.at("last_predict_dt").get<double>());
    EXPECT_TRUE(std::signbit(out.last_predict_dt) && out.last_predict_dt == 0.0);  // the -0.0 no-op
    EXPECT_TRUE(j.at("last_predict_is_noop").get<bool>());

    AnchorFieldDiffs w(std::string(GetParam()) + " " + run);
    const nlohmann::json& e = j.at("state_end");
    w.PropagatedState(e, {"pos", "rot_q_wxyz", "rot_R", "vel"}, out.end.pos, Wxyz(out.end.rot),
                      out.end.rot.toRotationMatrix(), out.end.vel, out.end.bg, out.end.ba);
    EXPECT_EQ(JsonVec3(e.at("offset_T_L_I")), out.end.offset_T_L_I);
    EXPECT_EQ(Eigen::Vector4d(JsonMatrix(e.at("offset_R_L_I_q_wxyz"))), Wxyz(out.end.offset_R_L_I));
    EXPECT_EQ(JsonVec3(e.at("grav")), out.end.grav.vec);
    EXPECT_EQ(e.at("grav_S2_length").get<double>(), out.end.grav.length);

    const nlohmann::json& c = j.at("covariance");
    EXPECT_EQ(c.at("block_sizes"), nlohmann::json({3, 3, 3, 3, 3, 3, 3, 2}));
    w.Covariance("covariance", JsonMatrix(c.at("matrix")), out.covariance);
    w.Jacobian("Phi_summed", JsonMatrix(j.at("Phi_summed").at("matrix")), out.Phi_summed);
    w.Covariance("Qd_summed", JsonMatrix(j.at("Qd_summed").at("matrix")), out.Qd_summed);
    w.Print();

    // The file holds FAST-LIO's identity rotation blocks: the variant with Exp(-w dt) there
    // (the half-angle meant) is off its Qd_summed by far more than rounding (correlation 1e-2
    // on static-0, which turns least; 0.1 to 0.4 elsewhere).
    FastLio2Propagation exact;
    ASSERT_TRUE(PropagateFastLio2Scan(samples_, params_, last_scan_end_, scan_end_, start, P0_,
                                      exact, FastLio2Transition::kExactRotation)
                    .ok());
    const ScaledDiff quirk =
        CorrelationScaleDiff(JsonMatrix(j.at("Qd_summed").at("matrix")), exact.Qd_summed);
    std::printf("  %-34s exact variant's Qd_summed off the file's by %.2g\n", "", quirk.d);
    EXPECT_GT(quirk.d, 1e-3) << "the exact variant should not reproduce FAST-LIO's numbers";
    EXPECT_EQ(exact.end.rot.coeffs(), out.end.rot.coeffs());  // the quirk is in the covariance only
  }

  FastLio2Parameters params_;
  std::vector<ImuSample> samples_;
  double last_scan_end_ = 0.0, scan_end_ = 0.0;
  FastLio2State start_;
  Vec3 gravity_ = Vec3::Zero();
  Mat23 P0_ = Mat23::Zero();
};

TEST_P(FastLio2Anchor, AsFastLioIsFastLioOwn) {
  EXPECT_EQ(start_.grav.length, 9.809);  // S2<double, 98090, 10000, 1>, not the case's 9.81
  ExpectRun("as_fastlio", FastLio2GravityAsBuilt(gravity_));
}

TEST_P(FastLio2Anchor, CaseGravityIsFastLioOwn) {
  ExpectRun("case_gravity", FastLio2GravityExact(gravity_));
}

INSTANTIATE_TEST_SUITE_P(Reference, FastLio2Anchor, ::testing::ValuesIn(kReferenceCaseIds),
                         CaseTestName);

}  // namespace
