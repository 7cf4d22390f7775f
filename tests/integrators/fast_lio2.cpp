// The FAST-LIO2 kernel's transition and what its `scalar_type(1/2)` quirk does
// (imuconv/kernels/fast_lio2.h):
//  - the exact variant's Phi_summed (rotation blocks Exp(-w dt)) against central differences
//    of the whole scan's propagation through IKFoM's own chart (MTK SO3 and S2 boxplus), on
//    all 23 columns; the as-built one (those blocks the identity) is not that derivative;
//  - the noise-only covariance Qd of both variants against one built from central differences
//    of each predict (its transition and its noise Jacobian): the exact variant's agrees, the
//    as-built one does not, and by how much is printed (the anchors' README: up to 60% on the
//    diagonal).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "imuconv/kernels/fast_lio2.h"
#include "imuconv_test.h"
#include "integrator_cases.h"
#include "json_quaternion.h"
#include "scale_aware.h"
#include "scheme_fact_declarations.h"

namespace {

// What the three propagators say of their noise and mean (scheme_fact_declarations.h;
// docs/fast-lio2.md, "What it does to a user: Monte Carlo"): ImuProcess averages the two ends
// of each step (centered cells); `fast_lio2` and `fast_lio2_exact_rotation` read densities,
// and `fast_lio2_as_configured` reads FAST-LIO's per-sample variances, which no density
// reproduces (not simulable: montecarlo flags the mismatch). All three give the mean alone,
// FastLio2IncrementMean (docs/fast-lio2.md: the same numbers as the full path, bit for bit;
// the transition and the noise reading do not enter it).
IMUCONV_SCHEME_FACTS(Propagator, fast_lio2, kCentered, kContinuous, true, kProvided);
IMUCONV_SCHEME_FACTS(Propagator, fast_lio2_exact_rotation, kCentered, kContinuous, true, kProvided);
IMUCONV_SCHEME_FACTS(Propagator, fast_lio2_as_configured, kCentered, kContinuous, false, kProvided);

using namespace imuconv;
using namespace imuconv::kernels;
using namespace imuconv::test;

struct FastLio2Scan {
  FastLio2Parameters params;
  std::vector<FastLio2Predict> predicts;
  FastLio2State start;
};

/// A reference case as one FAST-LIO2 scan (the anchors' construction): its densities as
/// per-sample variances sigma^2 / dt at the nominal rate, the scan from the first sample to
/// the last, the start state_s with gravity on FAST-LIO's S2 (length 9.809).
FastLio2Scan LoadScan(const std::string& id) {
  const nlohmann::json c = ReadJson(DataPath("reference/cases/" + id + ".json"));
  const std::vector<ImuSample> samples = CaseSamples(c);
  FastLio2Scan s;
  const double nominal_dt = 0.005;  // every reference case is sampled at 200 Hz
  const nlohmann::json& n = c.at("noise");
  auto per_sample = [&](const char* density) {
    return std::pow(n.at(density).get<double>(), 2) / nominal_dt;
  };
  s.params.gyr_cov = per_sample("gyro_noise_density");
  s.params.acc_cov = per_sample("accel_noise_density");
  s.params.b_gyr_cov = per_sample("gyro_random_walk");
  s.params.b_acc_cov = per_sample("accel_random_walk");
  EXPECT_TRUE(
      FastLio2ScanPredicts(samples, s.params, samples.front().t, samples.back().t, s.predicts)
          .ok());
  const nlohmann::json& st = c.at("state_s");
  const nlohmann::json& q = st.at("q_wxyz");
  s.start.rot = JsonQuaternionWxyz(q).normalized();
  s.start.pos = JsonVec3(st.at("p"));
  s.start.vel = JsonVec3(st.at("v"));
  s.start.bg = JsonVec3(st.at("bg"));
  s.start.ba = JsonVec3(st.at("ba"));
  s.start.grav = FastLio2GravityAsBuilt(JsonVec3(c.at("gravity")));
  return s;
}

FastLio2State PropagateState(const FastLio2Scan& s, FastLio2State x) {
  for (const FastLio2Predict& p : s.predicts) x = FastLio2PredictState(x, p.in, p.dt);
  return x;
}

/// The covariance recursion of FastLio2StepJacobians' F and dt G, from zero.
Mat23 NoiseCovariance(const FastLio2Scan& s, FastLio2Transition transition) {
  Mat23 Qd = Mat23::Zero();
  Eigen::Matrix<double, 12, 1> q;
  q << Vec3::Constant(s.params.gyr_cov), Vec3::Constant(s.params.acc_cov),
      Vec3::Constant(s.params.b_gyr_cov), Vec3::Constant(s.params.b_acc_cov);
  FastLio2State x = s.start;
  for (const FastLio2Predict& p : s.predicts) {
    Mat23 F;
    Eigen::Matrix<double, 23, 12> dt_G;
    FastLio2StepJacobians(x, p.in, p.dt, transition, F, dt_G);
    Qd = F * Qd * F.transpose() + dt_G * q.asDiagonal() * dt_G.transpose();
    x = FastLio2PredictState(x, p.in, p.dt);
  }
  return Qd;
}

Mat23 Transition(const FastLio2Scan& s, FastLio2Transition transition) {
  Mat23 Phi = Mat23::Identity();
  FastLio2State x = s.start;
  for (const FastLio2Predict& p : s.predicts) {
    Mat23 F;
    Eigen::Matrix<double, 23, 12> dt_G;
    FastLio2StepJacobians(x, p.in, p.dt, transition, F, dt_G);
    Phi = F * Phi;
    x = FastLio2PredictState(x, p.in, p.dt);
  }
  return Phi;
}

// Central differences with step h: truncation about h^2 times the third derivative (below
// 1e-9 relative here: the map is linear but for the rotation), and rounding. Each of the N
// predicts rounds the state sums (positions up to 1e3 m here) by about eps |x|; the perturbed
// runs round independently of each other, so the difference of two runs carries about
// sqrt(N) eps |x| (a random walk of N roundings), divided by 2h. Entries under 1e-4 of a
// matrix's largest are judged relative to that floor (RelativeAboveFloorDiff), so the bound
// on the relative difference is that rounding over the floor; at least 1e-7.
double FastLio2DifferenceBound(double h, std::size_t n_predict, double largest_value,
                               double largest_entry) {
  const double rounding =
      std::sqrt(double(n_predict)) * std::numeric_limits<double>::epsilon() * largest_value / h;
  return std::max(1e-7, rounding / (1e-4 * largest_entry));
}

double LargestValue(const FastLio2State& x) {
  return std::max({x.pos.cwiseAbs().maxCoeff(), x.vel.cwiseAbs().maxCoeff(), 1.0});
}

class FastLio2Derivatives : public ::testing::TestWithParam<const char*> {};

TEST_P(FastLio2Derivatives, ExactTransitionIsTheScansDerivative) {
  const FastLio2Scan s = LoadScan(GetParam());
  const FastLio2State nominal = PropagateState(s, s.start);
  constexpr double kStep = 1e-6;
  Mat23 numeric;
  for (int k = 0; k < kFastLio2Dof; ++k) {
    const Vec23 d = kStep * Vec23::Unit(k);
    const FastLio2State plus = PropagateState(s, FastLio2Boxplus(s.start, d));
    const FastLio2State minus = PropagateState(s, FastLio2Boxplus(s.start, -d));
    numeric.col(k) =
        (FastLio2Boxminus(plus, nominal) - FastLio2Boxminus(minus, nominal)) / (2 * kStep);
  }
  const Mat23 exact = Transition(s, FastLio2Transition::kExactRotation);
  const Mat23 as_built = Transition(s, FastLio2Transition::kAsFastLio);
  const ScaledDiff e = RelativeAboveFloorDiff(numeric, exact);
  const ScaledDiff a = RelativeAboveFloorDiff(numeric, as_built);
  const double bound = FastLio2DifferenceBound(kStep, s.predicts.size(), LargestValue(nominal),
                                               exact.cwiseAbs().maxCoeff());
  std::printf(
      "  %-13s Phi_summed vs central differences: exact %.2g at (%d,%d) (bound %.2g), as built "
      "%.2g at (%d,%d)\n",
      GetParam(), e.d, e.row, e.col, bound, a.d, a.row, a.col);
  EXPECT_LE(e.d, bound) << "at (" << e.row << "," << e.col << ")";
  // The identity in place of Exp(-w dt) leaves the rotation block of the scan at I instead of
  // the product of the Exp(-w dt): O(1) apart wherever the body turns (static-0 turns least).
  EXPECT_GT(a.d, 100 * bound) << "the as-built transition should not be the derivative";
}

TEST_P(FastLio2Derivatives, QuirkIsWhatMovesTheNoiseCovariance) {
  const FastLio2Scan s = LoadScan(GetParam());
  // Qd from central differences of each predict: its transition through the chart and its
  // noise Jacobian (gyro and accelerometer noise enter as w - ng, a - na; the bias walks as
  // bg += nbg dt, ba += nba dt, the model's own definition).
  constexpr double kStep = 1e-5;
  Eigen::Matrix<double, 12, 1> q;
  q << Vec3::Constant(s.params.gyr_cov), Vec3::Constant(s.params.acc_cov),
      Vec3::Constant(s.params.b_gyr_cov), Vec3::Constant(s.params.b_acc_cov);
  Mat23 numeric = Mat23::Zero();
  FastLio2State x = s.start;
  double largest = LargestValue(x);
  for (const FastLio2Predict& p : s.predicts) {
    const FastLio2State next = FastLio2PredictState(x, p.in, p.dt);
    largest = std::max(largest, LargestValue(next));
    Mat23 F;
    for (int k = 0; k < kFastLio2Dof; ++k) {
      const Vec23 d = kStep * Vec23::Unit(k);
      F.col(k) =
          (FastLio2Boxminus(FastLio2PredictState(FastLio2Boxplus(x, d), p.in, p.dt), next) -
           FastLio2Boxminus(FastLio2PredictState(FastLio2Boxplus(x, -d), p.in, p.dt), next)) /
          (2 * kStep);
    }
    Eigen::Matrix<double, 23, 12> G = Eigen::Matrix<double, 23, 12>::Zero();
    for (int k = 0; k < 6; ++k) {
      FastLio2Input plus = p.in, minus = p.in;
      Vec3& plus_axis = k < 3 ? plus.gyro : plus.acc;
      Vec3& minus_axis = k < 3 ? minus.gyro : minus.acc;
      plus_axis(k % 3) -= kStep;
      minus_axis(k % 3) += kStep;
      G.col(k) = (FastLio2Boxminus(FastLio2PredictState(x, plus, p.dt), next) -
                  FastLio2Boxminus(FastLio2PredictState(x, minus, p.dt), next)) /
                 (2 * kStep);
    }
    G.block<3, 3>(kFastLio2Bg, 6) = p.dt * Mat3::Identity();
    G.block<3, 3>(kFastLio2Ba, 9) = p.dt * Mat3::Identity();
    numeric = F * numeric * F.transpose() + G * q.asDiagonal() * G.transpose();
    x = next;
  }
  const Mat23 exact = NoiseCovariance(s, FastLio2Transition::kExactRotation);
  const Mat23 as_built = NoiseCovariance(s, FastLio2Transition::kAsFastLio);
  const ScaledDiff e = CorrelationScaleDiff(numeric, exact);
  const ScaledDiff a = CorrelationScaleDiff(numeric, as_built);
  double worst_diagonal = 0.0;
  int worst_index = 0;
  for (int i = 0; i < kFastLio2Dof; ++i) {
    if (!(exact(i, i) > 0.0)) continue;  // extrinsics and gravity: no noise reaches them
    const double r = std::abs(as_built(i, i) / exact(i, i) - 1.0);
    if (r > worst_diagonal) worst_diagonal = r, worst_index = i;
  }
  // Bound: each step's differences carry eps |x| / h of rounding relative to F's unit
  // entries (|x| the largest position or speed on the scan); F enters twice per step and the
  // N steps' roundings add as a random walk: 2 sqrt(N) eps |x| / h on the correlation scale,
  // times 3 for three standard deviations. The truncation, h^2 times the third derivative of
  // one step, is far below.
  const double bound = 3.0 * 2.0 * std::sqrt(double(s.predicts.size())) *
                       std::numeric_limits<double>::epsilon() * largest / kStep;
  std::printf(
      "  %-13s Qd vs per-step central differences: exact %.2g at (%d,%d) (bound %.2g), as built "
      "%.2g at"
      " (%d,%d); as built / exact - 1 on the diagonal up to %.3g (index %d)\n",
      GetParam(), e.d, e.row, e.col, bound, a.d, a.row, a.col, worst_diagonal, worst_index);
  EXPECT_LE(e.d, bound) << "at (" << e.row << "," << e.col << ")";
  // The identity rotation blocks are the whole difference: the as-built Qd is far outside
  // the differences' rounding (measured 0.014 on static-0, up to 0.37 on aggressive-0).
  EXPECT_GT(a.d, 100 * bound)
      << "the as-built covariance should differ from the step's linearization";
}

// Every input is hostile: each refusal names what is wrong, none propagates NaN or a
// reversed scan.
TEST(FastLio2Inputs, RefusesWhatItCannotPropagate) {
  std::vector<ImuSample> samples(3);
  for (int k = 0; k < 3; ++k) {
    samples[k].t = 0.005 * k;
    samples[k].accel = Vec3(0.0, 0.0, 9.81);
  }
  const FastLio2Parameters params;
  FastLio2State start;
  const Mat23 P0 = Mat23::Identity();
  FastLio2Propagation out;
  auto refusal = [&](const std::vector<ImuSample>& s, const FastLio2Parameters& p, double t0,
                     double t1, const FastLio2State& x, const Mat23& P) {
    const Status st = PropagateFastLio2Scan(s, p, t0, t1, x, P, out);
    EXPECT_FALSE(st.ok());
    return st.ok() ? std::string() : st.message();
  };
  ASSERT_TRUE(PropagateFastLio2Scan(samples, params, 0.0, 0.01, start, P0, out).ok());
  EXPECT_EQ(out.n_predict, 3);  // two pairs and the frame-end no-op

  EXPECT_NE(refusal({samples[0]}, params, 0.0, 0.01, start, P0).find("two IMU samples"),
            std::string::npos);
  std::vector<ImuSample> bad = samples;
  bad[1].gyro.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(refusal(bad, params, 0.0, 0.01, start, P0).find("sample 1 is not finite"),
            std::string::npos);
  bad = samples;
  bad[2].t = 0.001;
  EXPECT_NE(refusal(bad, params, 0.0, 0.01, start, P0).find("sample 2's time"), std::string::npos);
  EXPECT_NE(refusal(samples, params, 0.01, 0.0, start, P0).find("reversed"), std::string::npos);
  EXPECT_NE(refusal(samples, params, 0.02, 0.03, start, P0).find("no IMU sample"),
            std::string::npos);
  FastLio2Parameters p = params;
  p.mean_acc_norm = 0.0;
  EXPECT_NE(refusal(samples, p, 0.0, 0.01, start, P0).find("mean_acc"), std::string::npos);
  p = params;
  p.acc_cov = -1.0;
  EXPECT_NE(refusal(samples, p, 0.0, 0.01, start, P0).find("noise covariance"), std::string::npos);
  FastLio2State x = start;
  x.grav.length = 0.0;
  EXPECT_NE(refusal(samples, params, 0.0, 0.01, x, P0).find("S2 length"), std::string::npos);
  x = start;
  x.vel.x() = std::numeric_limits<double>::infinity();
  EXPECT_NE(refusal(samples, params, 0.0, 0.01, x, P0).find("start state"), std::string::npos);
  Mat23 P = P0;
  P(3, 4) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(refusal(samples, params, 0.0, 0.01, start, P).find("P0"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Reference, FastLio2Derivatives, ::testing::ValuesIn(kReferenceCaseIds),
                         CaseTestName);

}  // namespace
