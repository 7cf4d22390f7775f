// Covariance of each integrator against a Monte Carlo of noisy re-integrations.
//
// Truth model (paper, section 2.1): the true start state is x_s drawn from N(x^_s, cov_s) in the
// left chart; each sample carries white measurement noise n_k ~ N(0, sigma^2/dt I); the true
// biases follow a sampled random walk b_{k+1} = b_k + N(0, sigma_w^2 dt I). The truth is
// integrated by the same kernel: the bias path is folded into the samples, sample k becoming
// z_k - n_k - (b_k - b_0), and the kernel integrates from the true start (bias b_0), so it sees
// w = z_k - n_k - b_k at knot k; the true end biases are b_K.
//
// Comparison: each end error e = local(x^_e, x_e) is whitened with the predicted covariance,
// y = L^{-1} e (cov = L L^T). If the covariance is right, the sample second moment
// S = mean(y y^T) is I up to sampling error: an off-diagonal entry has standard deviation
// 1/sqrt(N), a diagonal one sqrt(2/N), each mean(y_i) 1/sqrt(N), and the mean NEES trace(S)
// has mean 15 and standard deviation sqrt(30/N). Every check uses 5 of those standard
// deviations: with the 120 + 15 entries of S that keeps the chance of a false alarm per test
// near 1e-4 (the seeds are fixed, so it either passes or not). With N = 10000 this resolves
// a ~7% error in a variance (diagonal tolerance 0.071), and a test below shows that scaling
// the noise densities by 0.8 is caught. Effects the truth model has beyond the linearised
// covariance are much smaller: linearisation errors ~|dtheta| ~ 3e-3 relative, and the
// discrete-vs-continuous difference of the noise model (midpoint and rk4 average or
// interpolate neighbouring noisy knots) is O(dt/T) = 0.5%.
#include <gtest/gtest.h>

#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "integrator_cases.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;
using kernels::Outputs;
namespace li = imuconv::left_idx;

constexpr int kRuns = 10000;

// A correlated start covariance small enough for the linearisation to hold to ~1e-3.
Mat15 StartCovariance() {
  Vec15 sigma;
  sigma << Vec3::Constant(0.02), Vec3::Constant(2e-3), Vec3::Constant(0.02), Vec3::Constant(2e-4),
      Vec3::Constant(2e-3);
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  Mat15 C = Mat15::Identity();
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < i; ++j) C(i, j) = 0.3 * normal(rng);
  const Mat15 L = sigma.asDiagonal() * C;
  return L * L.transpose();
}

struct McStatistics {
  double worst_sigmas = 0.0;  // max over entries of |S - I| and |mean| in their standard deviations
  double nees = 0.0;          // trace(S), expected 15
};

McStatistics Whiten(const std::vector<Vec15>& errors, const Mat15& cov) {
  const Eigen::LLT<Mat15> llt(cov);
  EXPECT_EQ(llt.info(), Eigen::Success);
  Mat15 S = Mat15::Zero();
  Vec15 mean = Vec15::Zero();
  for (const Vec15& e : errors) {
    const Vec15 y = llt.matrixL().solve(e);
    S.selfadjointView<Eigen::Lower>().rankUpdate(y);
    mean += y;
  }
  const double n = static_cast<double>(errors.size());
  S = S.selfadjointView<Eigen::Lower>();
  S /= n;
  mean /= n;
  McStatistics st;
  for (int i = 0; i < 15; ++i) {
    st.worst_sigmas = std::max(st.worst_sigmas, std::abs(mean[i]) * std::sqrt(n));
    for (int j = 0; j <= i; ++j) {
      const double sd = i == j ? std::sqrt(2.0 / n) : std::sqrt(1.0 / n);
      st.worst_sigmas = std::max(st.worst_sigmas, std::abs(S(i, j) - (i == j ? 1.0 : 0.0)) / sd);
    }
  }
  st.nees = S.trace();
  return st;
}

struct McCase {
  Integrator integrator;
  bool start_uncertainty;  // false: cov_s = 0, only the process noise is tested
};

class IntegratorMonteCarlo : public McNominalTest<McCase> {};

TEST_P(IntegratorMonteCarlo, WhitenedCovarianceIsIdentity) {
  const McCase mc = GetParam();
  const std::size_t K = knots_.size() - 1;
  in_.cov_s = mc.start_uncertainty ? StartCovariance() : Mat15::Zero();
  PropagationResult nominal;
  RunKernel(mc.integrator, in_, nominal);

  const Mat15 L_s = mc.start_uncertainty ? Mat15(in_.cov_s.llt().matrixL()) : Mat15::Zero();
  std::mt19937_64 rng(1000 + static_cast<int>(mc.integrator) * 10 + mc.start_uncertainty);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto normal3 = [&](double sd) {
    return Vec3(sd * normal(rng), sd * normal(rng), sd * normal(rng));
  };

  std::vector<ImuSample> noisy(knots_);
  std::vector<Vec15> errors;
  errors.reserve(kRuns);
  PropagationInput truth = in_;
  truth.cov_s.setZero();
  ASSERT_TRUE(
      MakeWindow(noisy.data(), noisy.size(), knots_.front().t, knots_.back().t, truth.window).ok());
  for (int run = 0; run < kRuns; ++run) {
    Vec15 z;
    for (int i = 0; i < 15; ++i) z[i] = normal(rng);
    LeftRetract(in_.x_s, L_s * z, truth.x_s);
    Vec3 bg = truth.x_s.bg, ba = truth.x_s.ba;
    for (std::size_t k = 0; k <= K; ++k) {
      const double dt = knots_[std::min(k + 1, K)].t - knots_[std::min(k + 1, K) - 1].t;
      noisy[k].gyro = knots_[k].gyro - normal3(in_.noise.gyro_noise_density / std::sqrt(dt)) -
                      (bg - truth.x_s.bg);
      noisy[k].accel = knots_[k].accel - normal3(in_.noise.accel_noise_density / std::sqrt(dt)) -
                       (ba - truth.x_s.ba);
      if (k < K) {
        bg += normal3(in_.noise.gyro_random_walk * std::sqrt(dt));
        ba += normal3(in_.noise.accel_random_walk * std::sqrt(dt));
      }
    }
    // MakeWindow copied the first and last knots; refresh them from the noisy samples.
    truth.window.first = noisy.front();
    truth.window.last = noisy.back();
    PropagationResult r;
    RunKernel<Outputs::State>(mc.integrator, truth, r);
    r.x_e.bg = bg;
    r.x_e.ba = ba;
    Vec15 e;
    LeftLocal(nominal.x_e, r.x_e, e);
    errors.push_back(e);
  }

  const McStatistics st = Whiten(errors, nominal.cov);
  const double n = kRuns;
  std::cout << "[ measured ] " << Name(mc.integrator)
            << (mc.start_uncertainty ? " with" : " without") << " start covariance, N = " << kRuns
            << ": worst whitened entry " << st.worst_sigmas << " sd (limit 5), NEES " << st.nees
            << " (15 +- " << std::sqrt(30.0 / n) << ")\n";
  RecordProperty("worst_sigmas", std::to_string(st.worst_sigmas));
  RecordProperty("nees", std::to_string(st.nees));
  EXPECT_LT(st.worst_sigmas, 5.0);
  EXPECT_NEAR(st.nees, 15.0, 5.0 * std::sqrt(30.0 / n));

  // Power: the same samples against the covariance predicted with noise densities 0.8x too small
  // (variances 0.64x) must be rejected, or the test above could not see a wrong noise model.
  PropagationInput wrong = in_;
  for (double* d : {&wrong.noise.gyro_noise_density, &wrong.noise.accel_noise_density,
                    &wrong.noise.gyro_random_walk, &wrong.noise.accel_random_walk})
    *d *= 0.8;
  PropagationResult wrong_result;
  RunKernel(mc.integrator, wrong, wrong_result);
  const McStatistics wrong_st = Whiten(errors, wrong_result.cov);
  std::cout << "[ measured ]   against 0.8x noise densities: worst " << wrong_st.worst_sigmas
            << " sd, NEES " << wrong_st.nees << "\n";
  EXPECT_GT(wrong_st.worst_sigmas, 5.0);
}

INSTANTIATE_TEST_SUITE_P(
    Integrators, IntegratorMonteCarlo,
    ::testing::Values(McCase{Integrator::Euler, true}, McCase{Integrator::Euler, false},
                      McCase{Integrator::Midpoint, true}, McCase{Integrator::Midpoint, false},
                      McCase{Integrator::Rk4, true}, McCase{Integrator::Rk4, false}),
    [](const ::testing::TestParamInfo<McCase>& info) {
      return std::string(Name(info.param.integrator)) +
             (info.param.start_uncertainty ? "_with_start_covariance" : "_noise_only");
    });

}  // namespace
