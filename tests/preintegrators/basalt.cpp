// The Basalt kernel's 9x9 covariance against Monte Carlo, and its bias Jacobians against
// central differences of its re-integration, on 1 s slices (200 steps) of reference cases, in
// both feedings, with the per-step variances sigma^2/dt the plugins use.
//
// Monte Carlo: white noise of variance density^2/dt on every sample (the held sample of a
// step is the one Basalt's feeding names), no bias random walk (Basalt's 9x9 has none: its
// VIO weights the bias change with separate factors). Each run is integrated with Basalt's
// step at the unchanged bias estimate; its error in the `basalt` chart is
//   e = [dp - dp^, Log(dR dR^T), dv - dv^]   (left rotation error).
// The whitened sample covariance must be I within 5 standard deviations of N Gaussian runs
// (whitened.h; the NEES trace of 9 dimensions has sqrt(18/N)).
#include "imuconv/kernels/basalt.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "bias_blocks.h"
#include "imuconv/so3.h"
#include "imuconv_test.h"
#include "reference_cases.h"
#include "scheme_fact_declarations.h"
#include "whitened.h"

namespace {

// What the three plugins say of their noise and mean (scheme_fact_declarations.h;
// docs/montecarlo.md): Basalt holds each sample over the step ending at it (backward;
// basalt_forward_zoh over the step it starts) and keeps the bias constant over the interval
// (the walk in the increment only); basalt_as_configured takes the white-noise numbers as
// per-sample standard deviations. None gives the mean alone: montecarlo's trials run the full
// preintegration.
IMUCONV_SCHEME_FACTS(Preintegrator, basalt, kBackward, kWalkInIncrementOnly, true, kNotProvided);
IMUCONV_SCHEME_FACTS(Preintegrator, basalt_forward_zoh, kForward, kWalkInIncrementOnly, true,
                     kNotProvided);
IMUCONV_SCHEME_FACTS(Preintegrator, basalt_as_configured, kBackward, kPerSampleStd, true,
                     kNotProvided);

using namespace imuconv;
using namespace imuconv::test;
namespace k = imuconv::kernels;

const double kNees9Tol = 5.0 * std::sqrt(18.0 / kRuns);  // 0.335

const char* Name(k::BasaltFeeding f) {
  return f == k::BasaltFeeding::kNative ? "native" : "forward_zoh";
}

/// The delta state's error in the `basalt` chart against a nominal one.
Vec9 ChartError(const k::BasaltPreintegration& nominal, const k::BasaltPreintegration& x) {
  Vec9 e;
  e << x.p - nominal.p, so3::Log(x.R * nominal.R.transpose()), x.v - nominal.v;
  return e;
}

void CheckMonteCarlo(const std::string& id, k::BasaltFeeding feeding) {
  SCOPED_TRACE(id + " " + Name(feeding));
  ReferenceCase rc = LoadReferenceCase(id);
  rc.samples.resize(201);  // 1 s, 200 steps
  const PreintegrationInput in = rc.Input();
  k::BasaltPreintegration nominal;
  ASSERT_TRUE(k::IntegrateBasalt(in, feeding, std::nullopt, nominal).ok());

  std::mt19937 rng(4242);
  std::normal_distribution<double> n01(0.0, 1.0);
  const auto randn3 = [&] { return Vec3(n01(rng), n01(rng), n01(rng)); };
  std::vector<Vec9> errors;
  errors.reserve(kRuns);
  std::vector<ImuSample> noisy = rc.samples;
  for (int run = 0; run < kRuns; ++run) {
    // The sample held over step j (of length dt_j) gets the variance density^2 / dt_j.
    for (std::size_t j = 0; j + 1 < rc.samples.size(); ++j) {
      const double dt = rc.samples[j + 1].t - rc.samples[j].t;
      const std::size_t held = feeding == k::BasaltFeeding::kNative ? j + 1 : j;
      noisy[held].gyro =
          rc.samples[held].gyro - (rc.noise.gyro_noise_density / std::sqrt(dt)) * randn3();
      noisy[held].accel =
          rc.samples[held].accel - (rc.noise.accel_noise_density / std::sqrt(dt)) * randn3();
    }
    PreintegrationInput noisy_in = in;
    noisy_in.window = WindowOver(noisy);
    k::BasaltPreintegration x;
    ASSERT_TRUE(k::IntegrateBasalt(noisy_in, feeding, std::nullopt, x, /*jacobians=*/false).ok());
    errors.push_back(ChartError(nominal, x));
  }
  const Whitened w = WhitenedStats<9>(nominal.cov, errors);
  std::printf(
      "[ MC      ] basalt %-11s %-12s N=%d: max|W_ii-1| %.3f (tol %.3f), max|W_ij| %.3f (tol "
      "%.3f), NEES %.3f "
      "(9 +- %.3f)\n",
      Name(feeding), id.c_str(), kRuns, w.diag, kDiagTol, w.off, kOffTol, w.nees, kNees9Tol);
  EXPECT_LT(w.diag, kDiagTol);
  EXPECT_LT(w.off, kOffTol);
  EXPECT_LT(std::abs(w.nees - 9.0), kNees9Tol);

  // The test has teeth: the same runs reject the covariance of the opposite rotation error
  // (R = Exp(-dtheta) R^, a JPL-style sign): the rotation-translation blocks change sign.
  Eigen::Matrix<double, 9, 9> T = Eigen::Matrix<double, 9, 9>::Identity();
  T.block<3, 3>(3, 3) = -Mat3::Identity();
  const Whitened wr =
      WhitenedStats<9>(Eigen::Matrix<double, 9, 9>(T * nominal.cov * T.transpose()), errors);
  std::printf(
      "[ MC      ]   with the rotation error's sign flipped: max|W_ii-1| %.3f, max|W_ij| %.3f\n",
      wr.diag, wr.off);
  EXPECT_GT(std::max(wr.diag, wr.off), kOffTol);
}

// Basalt's d_state_d_bg and d_state_d_ba are the exact derivatives of its own step (Jr of the
// full and the half step, the half-step rotation of the acceleration), so they agree with
// central differences of the re-integration (h = 1e-6, through the `basalt` chart) to the
// differences' own truncation and rounding: measured at most 1e-8 relative per 3x3 block,
// held to 1e-6 (a missing Jr or a wrong half-step gives 1e-3 or more on these slices).
void CheckBiasJacobians(const std::string& id, k::BasaltFeeding feeding) {
  SCOPED_TRACE(id + " " + Name(feeding));
  ReferenceCase rc = LoadReferenceCase(id);
  rc.samples.resize(201);
  const PreintegrationInput in = rc.Input();
  k::BasaltPreintegration x0;
  ASSERT_TRUE(k::IntegrateBasalt(in, feeding, std::nullopt, x0).ok());
  const Mat96 numeric = BiasCentralDifferences(
      in, /*accel_first=*/false, 1e-6, [&](const PreintegrationInput& moved) {
        k::BasaltPreintegration x;
        EXPECT_TRUE(k::IntegrateBasalt(moved, feeding, std::nullopt, x, /*jacobians=*/false).ok());
        return ChartError(x0, x);
      });
  Mat96 analytic;
  analytic << x0.d_state_d_bg, x0.d_state_d_ba;
  ExpectBiasBlocks(std::string("basalt ") + Name(feeding) + " " + id, analytic, numeric,
                   {"p", "theta", "v"}, {"bg", "ba"}, [](int) { return 1e-6; });
}

TEST(BasaltMonteCarlo, NativeAggressive) {
  CheckMonteCarlo("aggressive-0", k::BasaltFeeding::kNative);
}
TEST(BasaltMonteCarlo, ForwardZohJitter) {
  CheckMonteCarlo("jitter-0", k::BasaltFeeding::kForwardZoh);
}
TEST(BasaltBiasJacobians, NativeAggressive) {
  CheckBiasJacobians("aggressive-0", k::BasaltFeeding::kNative);
}
TEST(BasaltBiasJacobians, ForwardZohSmooth) {
  CheckBiasJacobians("smooth-0", k::BasaltFeeding::kForwardZoh);
}

}  // namespace
