// The FAST-LIO2 propagator plugins through the registry against FAST-LIO2's own numbers
// (tests/data/reference/anchors/fast-lio2, README.md there), on the ten reference cases:
// what a user of `fast_lio2_as_configured`, `fast_lio2` and `fast_lio2_exact_rotation` gets.
//
// - `fast_lio2_as_configured` with the file's four configuration numbers (gyr_cov, acc_cov,
//   b_gyr_cov, b_acc_cov), the gravity of each run given as the caller gives it (the case's,
//   and the case's rescaled to FAST-LIO's S2 length 9.809 for `as_fastlio`), P0 = the case's
//   cov_s_left converted by the registry: the end state, and the [pos, rot, vel, bg, ba] rows
//   and columns of the file's 23x23 covariance, Phi_summed and Qd_summed, in the plugin's
//   native `fast_lio2` and, converted by the registry, in `left` (against the file's numbers
//   converted by hand: dtheta_left = R drot).
// - `fast_lio2` (densities): its per-sample variances are sigma^2 times the window's mean rate,
//   200 to rounding on the eight regularly sampled cases, where it is then FAST-LIO's own
//   run; on the two jittered ones (mean rate 200.15 and 199.81 against the file's nominal 200)
//   it is `fast_lio2_as_configured` given sigma^2 times that mean rate.
// - `fast_lio2_exact_rotation`: the kernel's exact-rotation variant, restricted.
// - No gravity (preintegration by propagation, the note's section 3.1): the covariance and
//   transition do not involve gravity, and the mean moves by gravity's exact first-order
//   terms.
//
// Tolerances: anchors.h (1e-8 by the note's metric; 1e-9 on the correlation scale and
// relative to the transition's entries above 1e-4 of its largest), as tests/reference/
// fast_lio2_anchor.cpp: the same kernel, reached through the registry, whose conversions add
// products of O(1) rotations (rounding, 1e-15 relative).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "anchor_field_diffs.h"
#include "anchors.h"
#include "imuconv/bridge.h"
#include "imuconv/kernels/fast_lio2.h"
#include "imuconv/preintegrator.h"
#include "imuconv/so3.h"
#include "imuconv/window.h"
#include "imuconv_test.h"
#include "reference_case.h"
#include "scale_aware.h"

namespace {

using namespace imuconv;
using namespace imuconv::kernels;
using namespace imuconv::test;

/// The [pos, rot, vel, bg, ba] rows and columns of a 23x23 matrix of the file.
Mat15 FifteenOf(const Eigen::MatrixXd& m23) {
  const int at[5] = {kFastLio2Pos, kFastLio2Rot, kFastLio2Vel, kFastLio2Bg, kFastLio2Ba};
  Mat15 out;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) out.block<3, 3>(3 * i, 3 * j) = m23.block<3, 3>(at[i], at[j]);
  return out;
}

/// fast_lio2 -> left at x, derived by hand: dtheta_left = R drot, the rest in place.
Mat15 FastLio2ToLeft(const Mat3& R) {
  Mat15 J = Mat15::Identity();
  J.block<3, 3>(3, 3) = R;
  return J;
}

class FastLio2Plugins : public AnchorCaseJsonTest {
 protected:
  FastLio2Plugins() : AnchorCaseJsonTest("fast-lio2") {}
  void SetUp() override {
    samples_ = CaseSamples(case_);
    ASSERT_TRUE(MakeWindow(samples_.data(), samples_.size(), samples_.front().t, samples_.back().t,
                           in_.window)
                    .ok());
    const nlohmann::json& st = case_.at("state_s");
    const nlohmann::json& q = st.at("q_wxyz");
    in_.x_s.R = JsonQuaternionWxyz(q).normalized().toRotationMatrix();
    in_.x_s.p = JsonVec3(st.at("p"));
    in_.x_s.v = JsonVec3(st.at("v"));
    in_.x_s.bg = JsonVec3(st.at("bg"));
    in_.x_s.ba = JsonVec3(st.at("ba"));
    gravity_ = JsonVec3(case_.at("gravity"));
    cov_left_ = JsonMatrix(case_.at("cov_s_left").at("matrix"));
    configured_.gyro_noise_density = inputs_.at("gyr_cov").get<double>();
    configured_.accel_noise_density = inputs_.at("acc_cov").get<double>();
    configured_.gyro_random_walk = inputs_.at("b_gyr_cov").get<double>();
    configured_.accel_random_walk = inputs_.at("b_acc_cov").get<double>();
  }

  /// The gravity of run `run` as a user gives it to the plugins.
  Vec3 RunGravity(const char* run) const {
    return std::string(run) == "as_fastlio" ? Vec3(gravity_.normalized() * 9.809) : gravity_;
  }

  /// `id` with `noise` against the file's run `run`, in `fast_lio2` and in `left`.
  void ExpectRun(const char* id, const ImuNoise& noise, const char* run) {
    const Registry& reg = Plugins();
    const nlohmann::json& j = anchor_.at(run);
    PropagationInput in = in_;
    in.noise = noise;
    in.gravity = RunGravity(run);
    in.cov_s = reg.convert_covariance("left", "fast_lio2", in.x_s, cov_left_);
    const PropagationResult r = reg.propagate(id, "fast_lio2", in);
    in.cov_s.setZero();
    const PropagationResult q = reg.propagate(id, "fast_lio2", in);

    AnchorFieldDiffs w(std::string(GetParam()) + " " + id + " " + run);
    const nlohmann::json& e = j.at("state_end");
    w.Metric("pos", JsonMatrix(e.at("pos")), r.x_e.p);
    w.Metric("rot_R", JsonMatrix(e.at("rot_R")), r.x_e.R);
    w.Metric("vel", JsonMatrix(e.at("vel")), r.x_e.v);
    w.Metric("bg", JsonMatrix(e.at("bg")), r.x_e.bg);
    w.Metric("ba", JsonMatrix(e.at("ba")), r.x_e.ba);
    const Mat15 cov = FifteenOf(JsonMatrix(j.at("covariance").at("matrix")));
    const Mat15 phi = FifteenOf(JsonMatrix(j.at("Phi_summed").at("matrix")));
    const Mat15 qd = FifteenOf(JsonMatrix(j.at("Qd_summed").at("matrix")));
    w.Covariance("covariance", cov, r.cov);
    w.Jacobian("Phi_summed", phi, r.Phi);
    w.Covariance("Qd_summed", qd, q.cov);

    // The same run asked for in `left`: the registry converts the plugin's numbers.
    PropagationInput in_left = in_;
    in_left.noise = noise;
    in_left.gravity = in.gravity;
    in_left.cov_s = cov_left_;
    const PropagationResult l = reg.propagate(id, "left", in_left);
    const Mat3 R_e = JsonMatrix(e.at("rot_R"));
    const Mat15 J_e = FastLio2ToLeft(R_e), J_s = FastLio2ToLeft(in_.x_s.R);
    w.Covariance("covariance in left", J_e * cov * J_e.transpose(), l.cov);
    w.Jacobian("Phi_summed in left", J_e * phi * J_s.inverse(), l.Phi);
    w.Print();
  }

  std::vector<ImuSample> samples_;
  PropagationInput in_;
  Vec3 gravity_ = Vec3::Zero();
  Mat15 cov_left_ = Mat15::Zero();
  ImuNoise configured_;
};

TEST_P(FastLio2Plugins, AsConfiguredIsFastLioOwn) {
  ExpectRun("fast_lio2_as_configured", configured_, "case_gravity");
  ExpectRun("fast_lio2_as_configured", configured_, "as_fastlio");
}

TEST_P(FastLio2Plugins, DensitiesAreFastLioOwnAtTheMeanRate) {
  const ImuNoise densities = CaseNoise(case_);
  const double rate = (samples_.size() - 1) / (samples_.back().t - samples_.front().t);
  const double nominal = inputs_.at("imu_rate").get<double>();
  // Regular sampling: 2000 steps of 5 ms to rounding of the stamps (4e-13 relative).
  if (std::abs(rate / nominal - 1.0) < 1e-12) {
    ExpectRun("fast_lio2", densities, "case_gravity");
    ExpectRun("fast_lio2", densities, "as_fastlio");
    return;
  }
  // Jittered: `fast_lio2` is FAST-LIO configured with sigma^2 times the mean rate (the same
  // products formed in the same order: bit for bit), which is the file's run only up to
  // the rate's ratio, far above rounding.
  EXPECT_GT(std::abs(rate / nominal - 1.0), 1e-4) << "a jittered case with the nominal mean rate";
  ImuNoise configured;
  configured.gyro_noise_density =
      densities.gyro_noise_density * densities.gyro_noise_density * rate;
  configured.accel_noise_density =
      densities.accel_noise_density * densities.accel_noise_density * rate;
  configured.gyro_random_walk = densities.gyro_random_walk * densities.gyro_random_walk * rate;
  configured.accel_random_walk = densities.accel_random_walk * densities.accel_random_walk * rate;
  PropagationInput in = in_;
  in.gravity = gravity_;
  in.cov_s.setZero();
  in.noise = densities;
  const PropagationResult d = Plugins().propagate("fast_lio2", "fast_lio2", in);
  in.noise = configured;
  const PropagationResult c = Plugins().propagate("fast_lio2_as_configured", "fast_lio2", in);
  EXPECT_EQ(d.cov, c.cov);
  const Mat15 qd = FifteenOf(JsonMatrix(anchor_.at("case_gravity").at("Qd_summed").at("matrix")));
  EXPECT_GT(CorrelationScaleDiff(qd, d.cov).d, 1e-5);
}

TEST_P(FastLio2Plugins, ExactRotationIsTheKernelsExactVariant) {
  // The kernel's own 23-dimensional run with Exp(-w dt) in F's rotation block (the scan
  // driven directly, from the file's P0, with the densities' sigma^2 times the mean rate),
  // restricted to the 15 blocks.
  PropagationInput in = in_;
  in.noise = CaseNoise(case_);
  in.gravity = gravity_;
  in.cov_s = Plugins().convert_covariance("left", "fast_lio2", in.x_s, cov_left_);
  const PropagationResult r = Plugins().propagate("fast_lio2_exact_rotation", "fast_lio2", in);
  const double rate = (samples_.size() - 1) / (samples_.back().t - samples_.front().t);
  FastLio2Parameters params;
  params.gyr_cov = in.noise.gyro_noise_density * in.noise.gyro_noise_density * rate;
  params.acc_cov = in.noise.accel_noise_density * in.noise.accel_noise_density * rate;
  params.b_gyr_cov = in.noise.gyro_random_walk * in.noise.gyro_random_walk * rate;
  params.b_acc_cov = in.noise.accel_random_walk * in.noise.accel_random_walk * rate;
  FastLio2State start;
  start.pos = in.x_s.p;
  start.rot = Eigen::Quaterniond(in.x_s.R);
  start.vel = in.x_s.v;
  start.bg = in.x_s.bg;
  start.ba = in.x_s.ba;
  start.grav = FastLio2GravityExact(gravity_);
  FastLio2Propagation k;
  ASSERT_TRUE(PropagateFastLio2Scan(samples_, params, samples_.front().t, samples_.back().t, start,
                                    JsonMatrix(inputs_.at("P0").at("matrix")), k,
                                    FastLio2Transition::kExactRotation)
                  .ok());
  AnchorFieldDiffs w(std::string(GetParam()) + " fast_lio2_exact_rotation");
  w.Metric("rot_R", Mat3(k.end.rot.toRotationMatrix()), r.x_e.R);
  w.Metric("pos", k.end.pos, r.x_e.p);
  w.Metric("vel", k.end.vel, r.x_e.v);
  w.Covariance("covariance", FifteenOf(k.covariance), r.cov);
  w.Jacobian("Phi", FifteenOf(k.Phi_summed), r.Phi);
  w.Print();
  // and it is not FAST-LIO's: the transition differs from the file's by far more than the
  // 1e-9 rounding bound (Exp(-w dt) against I compounded over 2000 steps; least on static-0,
  // which turns least).
  const Mat15 phi = FifteenOf(JsonMatrix(anchor_.at("case_gravity").at("Phi_summed").at("matrix")));
  const ScaledDiff quirk = RelativeAboveFloorDiff(phi, r.Phi);
  EXPECT_GT(quirk.d, 1e-6);
  // What the quirk does to the noise alone (docs/fast-lio2.md): FAST-LIO's Qd against the
  // exact variant's, the largest ratio of variances per block and on the correlation scale.
  in.cov_s.setZero();
  const PropagationResult q_exact =
      Plugins().propagate("fast_lio2_exact_rotation", "fast_lio2", in);
  const PropagationResult q_built = Plugins().propagate("fast_lio2", "fast_lio2", in);
  double ratio[3] = {0.0, 0.0, 0.0};  // pos, rot, vel: max |built/exact - 1| on the diagonal
  for (int b = 0; b < 3; ++b)
    for (int i = 3 * b; i < 3 * b + 3; ++i)
      ratio[b] = std::max(ratio[b], std::abs(q_built.cov(i, i) / q_exact.cov(i, i) - 1.0));
  std::printf(
      "  %-14s Phi off FAST-LIO's by %.2g; FAST-LIO's Qd vs the exact variant's: "
      "diagonal pos %.3g rot %.3g vel %.3g, correlation scale %.3g\n",
      GetParam(), quirk.d, ratio[0], ratio[1], ratio[2],
      CorrelationScaleDiff(q_exact.cov, q_built.cov).d);
}

TEST_P(FastLio2Plugins, WithoutGravityOnlyTheMeanMoves) {
  // FAST-LIO's step: vel += g dt, pos += vel dt from the pre-step state, so over steps dt_k
  // ending at T the gravity adds g T to vel and g sum_k (t_k - t_0) dt_k to pos; the
  // covariance and transition of [pos, rot, vel, bg, ba] do not involve g at all. Rounding:
  // the same 2000 steps with and without g (relative 1e-12 of positions up to 500 m).
  PropagationInput in = in_;
  in.noise = CaseNoise(case_);
  in.cov_s = Plugins().convert_covariance("left", "fast_lio2", in.x_s, cov_left_);
  in.gravity = gravity_;
  const PropagationResult with = Plugins().propagate("fast_lio2", "fast_lio2", in);
  in.gravity.setZero();
  const PropagationResult without = Plugins().propagate("fast_lio2", "fast_lio2", in);
  double T = 0.0, pos_weight = 0.0;
  for (std::size_t k = 0; k + 1 < samples_.size(); ++k) {
    const double dt = samples_[k + 1].t - samples_[k].t;
    pos_weight += (samples_[k].t - samples_.front().t) * dt;
    T += dt;
  }
  AnchorFieldDiffs w(std::string(GetParam()) + " fast_lio2 without gravity");
  w.Metric("R", with.x_e.R, without.x_e.R);
  w.Metric("vel", with.x_e.v, Vec3(without.x_e.v + gravity_ * T));
  w.Metric("pos", with.x_e.p, Vec3(without.x_e.p + gravity_ * pos_weight));
  w.Covariance("covariance", with.cov, without.cov);
  w.Jacobian("Phi", with.Phi, without.Phi);
  w.Print();
}

TEST_P(FastLio2Plugins, IncrementMeanIsPreintegrationByPropagationBitForBit) {
  // The kernel's mean alone (Monte Carlo trials) against the registry's preintegration by
  // propagation with `fast_lio2`: the same predicts from the same start, so the same bits.
  const PreintegrationMethod method =
      ResolvePreintegrationMethod(Plugins(), PluginKind::Propagator, "fast_lio2");
  const Preintegrated full =
      Preintegrate(Plugins(), method, in_.window, in_.x_s.bg, in_.x_s.ba, CaseNoise(case_));
  const PreintegrationInput in =
      PreintegrationInputOf(in_.window, in_.x_s.bg, in_.x_s.ba, CaseNoise(case_));
  PreintIncrement mean;
  ASSERT_TRUE(FastLio2IncrementMean(in, mean).ok());
  EXPECT_EQ(mean.dR, full.delta.dR);
  EXPECT_EQ(mean.dp, full.delta.dp);
  EXPECT_EQ(mean.dv, full.delta.dv);
  EXPECT_EQ(mean.dbg, Vec3::Zero());
  EXPECT_EQ(mean.dba, Vec3::Zero());
  // and each plugin gives it as its increment_mean() (the transition and the noise reading
  // do not enter the mean)
  for (const char* id : {"fast_lio2", "fast_lio2_exact_rotation", "fast_lio2_as_configured"}) {
    PreintIncrement by_plugin;
    ASSERT_TRUE(Plugins().propagator(id)->increment_mean(in, by_plugin).ok()) << id;
    EXPECT_EQ(by_plugin.dR, mean.dR) << id;
    EXPECT_EQ(by_plugin.dp, mean.dp) << id;
    EXPECT_EQ(by_plugin.dv, mean.dv) << id;
  }
}

INSTANTIATE_TEST_SUITE_P(Reference, FastLio2Plugins, ::testing::ValuesIn(kReferenceCaseIds),
                         CaseTestName);

}  // namespace
