// OKVIS2's own numbers (tests/data/reference/anchors/okvis2, README.md there): its
// ImuError::propagation, redoPreintegration and EvaluateWithMinimalJacobians on each of the
// ten reference cases, against imuconv's OKVIS2 kernel (imuconv/kernels/okvis2.h), in OKVIS's
// error states ([r, alpha, v, bg, ba], rotation left in the world or the first frame).
//
// Tolerances: anchors.h (1e-8 by the note's metric; covariances also on the correlation scale
// and Jacobians relative to entries above 1e-4 of the largest, at 1e-9). The same formulas
// are evaluated in another order (one covariance for the four densities instead of one per
// density weighted at the end; products grouped otherwise; FMA here, none upstream).
// `information` is inverted from P_delta by an eigen-decomposition on both sides and is
// compared on its correlation scale (ExpectPreintegration says why).
// The `whitened` outputs are S times `raw`, with S's row signs the eigen-solver's choice
// (the README): they are checked sign-free, |whitened residual|^2 = raw^T information raw.
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
#include "imuconv/kernels/okvis2.h"
#include "imuconv_test.h"
#include "reference_case.h"
#include "scale_aware.h"

namespace {

using namespace imuconv;
using namespace imuconv::kernels;
using namespace imuconv::test;  // DataPath, JsonMatrix, MaxEntryDiff, the anchors' bounds

Okvis2State JsonState(const nlohmann::json& s) {
  Okvis2State x;
  x.q = JsonQuaternionWxyz(s.at("q_wxyz"));
  IMUCONV_READ_ANCHOR_MEMBERS(JsonVec3, s, x, (r)(v)(bg)(ba));
  return x;
}

std::int64_t JsonOkvisTime(const nlohmann::json& t) {
  return t.at("sec").get<std::int64_t>() * 1000000000 + t.at("nsec").get<std::int64_t>();
}

class Okvis2Anchor : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    anchor_ = AnchorJson("okvis2", GetParam());
    const nlohmann::json case_json = CaseJson(GetParam());
    const nlohmann::json& in = anchor_.at("inputs");
    // The anchor ran with the case's densities as OKVIS's sigma_*_c.
    const nlohmann::json& noise = case_json.at("noise");
    params_.sigma_g_c = noise.at("gyro_noise_density").get<double>();
    params_.sigma_a_c = noise.at("accel_noise_density").get<double>();
    params_.sigma_gw_c = noise.at("gyro_random_walk").get<double>();
    params_.sigma_aw_c = noise.at("accel_random_walk").get<double>();
    ASSERT_EQ(in.at("sigma_g_c").get<double>(), params_.sigma_g_c);
    ASSERT_EQ(in.at("sigma_a_c").get<double>(), params_.sigma_a_c);
    ASSERT_EQ(in.at("sigma_gw_c").get<double>(), params_.sigma_gw_c);
    ASSERT_EQ(in.at("sigma_aw_c").get<double>(), params_.sigma_aw_c);
    ASSERT_EQ(in.at("a_max").get<double>(), params_.a_max);
    ASSERT_EQ(in.at("g_max").get<double>(), params_.g_max);
    ASSERT_EQ(in.at("g").get<double>(), -case_json.at("gravity")[2].get<double>());

    for (const ImuSample& s : CaseSamples(case_json)) {
      Okvis2Sample o;
      ASSERT_TRUE(Okvis2TimeFromSeconds(s.t, o.t_ns).ok());
      o.gyro = s.gyro;
      o.accel = s.accel;
      samples_.push_back(o);
    }
    ASSERT_EQ(in.at("n_measurements").get<std::size_t>(), samples_.size());
    t0_ = samples_.front().t_ns;
    t1_ = samples_.back().t_ns;
    // The stamps are OKVIS's own: the file's start and end as okvis::Time holds them.
    ASSERT_EQ(JsonOkvisTime(in.at("t_start")), t0_);
    ASSERT_EQ(JsonOkvisTime(in.at("t_end")), t1_);
    start_ = JsonState(in.at("state_start"));
    const nlohmann::json& st = case_json.at("state_s");
    ASSERT_EQ(Wxyz(start_.q), Eigen::Vector4d(JsonMatrix(st.at("q_wxyz"))));
    ASSERT_EQ(start_.r, JsonVec3(st.at("p")));
    ASSERT_EQ(start_.v, JsonVec3(st.at("v")));
    ASSERT_EQ(start_.bg, JsonVec3(st.at("bg")));
    ASSERT_EQ(start_.ba, JsonVec3(st.at("ba")));
  }

  /// The preintegrated quantities of one redoPreintegration against the file's.
  void ExpectPreintegration(const nlohmann::json& j, const Okvis2Preintegration& p,
                            const std::string& label) {
    AnchorFieldDiffs w(label);
    EXPECT_EQ(j.at("redoCounter").get<int>(), 1) << label;
    w.Metric("Delta_q_wxyz", JsonMatrix(j.at("Delta_q_wxyz")), Wxyz(p.Delta_q));
    w.Metric("Delta_R", JsonMatrix(j.at("Delta_R")), p.Delta_q.toRotationMatrix());
    IMUCONV_CHECK_ANCHOR_MEMBERS(w.Jacobian, j, p, (C_integral)(C_doubleintegral));
    IMUCONV_CHECK_ANCHOR_MEMBERS(w.Metric, j, p, (acc_integral)(acc_doubleintegral));
    IMUCONV_CHECK_ANCHOR_MEMBERS(w.Jacobian, j, p, (dalpha_db_g)(dv_db_g)(dp_db_g));
    Vec9 ref_point;
    ref_point << Vec3::Zero(), p.bg_ref, p.ba_ref;
    // speedAndBiases_ref also holds the speed it was called with; only the biases are used.
    EXPECT_EQ(Eigen::VectorXd(JsonMatrix(j.at("speedAndBiases_ref"))).tail<6>(),
              ref_point.tail<6>())
        << label;
    w.Covariance("P_delta", JsonMatrix(j.at("P_delta").at("matrix")), p.P_delta);
    // The information is P_delta's inverse by an eigen-decomposition (upstream's
    // PseudoInverse::symmSqrtU; here Eigen's same solver). P_delta agrees to about 4e-14, but
    // any such inverse is exact only to about eps times P_delta's condition number (its
    // smallest eigenvalues, the bias directions near 1e-12 beside positions near 1e-2, carry
    // an absolute error of eps times the largest): 2.4e8 to 2.4e11 on these cases. Entries
    // that cancel (a velocity-rotation or bias cross term, small beside its diagonal) then
    // differ by up to 1.5e-5 by the metric, whoever inverts. What a residual's weight depends
    // on is each entry relative to its diagonal, sqrt(I_ii I_jj): compared there, within the
    // anchors' scaled 1e-9 or that rounding bound, eps cond(P_delta), whichever is larger
    // (measured: at most 7.9e-10, smooth-3; a wrong block or a missing symmetrization is
    // O(1) there).
    const Eigen::MatrixXd information = JsonMatrix(j.at("information"));
    const ScaledDiff info = CorrelationScaleDiff(information, p.information);
    const Eigen::SelfAdjointEigenSolver<Mat15> eig(p.P_delta);
    const double condition = eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff();
    const double info_tol =
        std::max(kAnchorScaledTol, std::numeric_limits<double>::epsilon() * condition);
    EXPECT_LE(info.d, info_tol) << label << ": information at (" << info.row << "," << info.col
                                << ")";
    w.Print();
    std::printf("  %-34s information %.2g (bound %.2g; by the metric %.2g)\n", "", info.d, info_tol,
                MaxEntryDiff(information, p.information));
  }

  /// One EvaluateWithMinimalJacobians: the raw residual and Jacobians against the file's, and
  /// the whitened residual's norm against raw^T information raw.
  void ExpectEvaluation(const nlohmann::json& j, const Okvis2ImuErrorTerms& t,
                        const Mat15& information, const std::string& label) {
    AnchorFieldDiffs w(label);
    const nlohmann::json& raw = j.at("raw");
    w.Metric("residual", JsonMatrix(raw.at("residual")), t.residual);
    IMUCONV_CHECK_ANCHOR_MEMBERS(w.Jacobian, raw, t,
                                 (jacobian_pose_0)(jacobian_pose_1)(jacobian_speedbias_0)(
                                     jacobian_speedbias_1)(jacobian_pose_0_minimal)(
                                     jacobian_pose_1_minimal));
    const Eigen::VectorXd whitened = JsonMatrix(j.at("whitened").at("residual"));
    const double chi2_file = whitened.squaredNorm();
    const double chi2 = t.residual.dot(information * t.residual);
    EXPECT_NEAR(chi2, chi2_file, kAnchorMetricTol * std::max(1.0, chi2_file)) << label << ": chi2";
    w.Print();
  }

  nlohmann::json anchor_;
  Okvis2ImuParameters params_;
  std::vector<Okvis2Sample> samples_;
  std::int64_t t0_ = 0, t1_ = 0;
  Okvis2State start_;
};

TEST_P(Okvis2Anchor, PropagationIsOkvisOwn) {
  Okvis2Propagation out;
  ASSERT_TRUE(PropagateOkvis2(samples_, params_, start_, t0_, t1_, out).ok());
  const nlohmann::json& j = anchor_.at("propagation");
  EXPECT_EQ(out.steps, j.at("n_steps").get<int>());
  EXPECT_NEAR(out.Delta_t, anchor_.at("inputs").at("Delta_t").get<double>(),
              1e-12);  // 2000 sums of dt
  AnchorFieldDiffs w(std::string(GetParam()) + " propagation");
  w.PropagatedState(j.at("state_end"), {"r", "q_wxyz", "C", "v"}, out.end.r, Wxyz(out.end.q),
                    out.end.q.toRotationMatrix(), out.end.v, out.end.bg, out.end.ba);
  w.Covariance("covariance", JsonMatrix(j.at("covariance").at("matrix")), out.covariance);
  w.Jacobian("jacobian", JsonMatrix(j.at("jacobian").at("matrix")), out.jacobian);
  w.Print();
}

TEST_P(Okvis2Anchor, ImuErrorIsOkvisOwn) {
  const nlohmann::json& ie = anchor_.at("imu_error");
  const Okvis2State state_0 = JsonState(ie.at("state_0")), state_1 = JsonState(ie.at("state_1"));
  const double Delta_t = Okvis2Seconds(t1_ - t0_);
  // The first evaluation integrates at state_0's biases (never integrated before).
  Okvis2Preintegration at_lin;
  EXPECT_TRUE(Okvis2RedoesPreintegration(at_lin, state_0.bg, samples_.size()));
  ASSERT_TRUE(PreintegrateOkvis2(samples_, params_, state_0.bg, state_0.ba, t0_, t1_, at_lin).ok());
  ExpectPreintegration(ie.at("preintegration"), at_lin,
                       std::string(GetParam()) + " preintegration");
  ExpectEvaluation(ie.at("at_lin_bias"),
                   EvaluateOkvis2ImuError(at_lin, params_, Delta_t, state_0, state_1),
                   at_lin.information, std::string(GetParam()) + " at the linearization bias");

  // At a new bias upstream keeps the integration (2001 samples, not fewer than 50) and
  // corrects to first order.
  const Okvis2State state_0_new = JsonState(ie.at("state_0_new_bias"));
  EXPECT_FALSE(Okvis2RedoesPreintegration(at_lin, state_0_new.bg, samples_.size()));
  EXPECT_EQ(ie.at("redoCounter_after_new_bias").get<int>(), 1);
  ExpectEvaluation(ie.at("at_new_bias"),
                   EvaluateOkvis2ImuError(at_lin, params_, Delta_t, state_0_new, state_1),
                   at_lin.information, std::string(GetParam()) + " at the new bias");

  // A fresh ImuError evaluated first at the new bias integrates there.
  const nlohmann::json& re = ie.at("repropagated");
  Okvis2Preintegration at_new;
  ASSERT_TRUE(
      PreintegrateOkvis2(samples_, params_, state_0_new.bg, state_0_new.ba, t0_, t1_, at_new).ok());
  ExpectPreintegration(re.at("preintegration"), at_new, std::string(GetParam()) + " repropagated");
  ExpectEvaluation(re.at("at_new_bias"),
                   EvaluateOkvis2ImuError(at_new, params_, Delta_t, state_0_new, state_1),
                   at_new.information, std::string(GetParam()) + " repropagated at the new bias");
}

INSTANTIATE_TEST_SUITE_P(Reference, Okvis2Anchor, ::testing::ValuesIn(kReferenceCaseIds),
                         CaseTestName);

}  // namespace
