// Monte Carlo on synthetic data with known biases: the biases estimated by a small problem fall
// within their reported 3 sigma (ceres::Covariance, tangent space) at the rate a Gaussian
// predicts, and their normalized errors have a mean square of 1.
#include <gtest/gtest.h>

#include <cmath>

#include "ceres_problem.h"
#include "imuconv/chi_square.h"
#include "imuconv_test.h"

namespace imuconv::ceres_test {
namespace {

// Pr(X > m) for X ~ Binomial(n, p), summed from the top term down (each term from the last).
double BinomialUpperTail(int n, double p, int m) {
  double term = std::pow(1.0 - p, n);  // Pr(X = 0)
  double cdf = term;
  for (int k = 1; k <= m; ++k) {
    term *= (n - k + 1) / static_cast<double>(k) * p / (1.0 - p);
    cdf += term;
  }
  return 1.0 - cdf;
}

TEST(CeresBiasMonteCarlo, EstimatedBiasesWithinTheirCovarianceAsAGaussianPredicts) {
  const Registry& reg = test::Plugins();
  const PreintegrationMethod method =
      ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, "manifold");
  const BlockLabels left = reg.state_convention("left")->labels();
  const int bg_at = BlockOffset(left, "bg"), ba_at = BlockOffset(left, "ba");
  // N runs: each a 6-keyframe second at 200 Hz, solved and its covariance computed (a few ms).
  constexpr int kRuns = 300;
  constexpr int kKeyframes = 6;
  std::mt19937 rng(4242);
  int outside_3_sigma = 0;
  double sum_z2 = 0.0, sum_nees = 0.0;
  for (int run_index = 0; run_index < kRuns; ++run_index) {
    const SimulatedRun run = SimulateAtTypicalBiases(kKeyframes, 0.2, 200.0, true, rng);
    const Measurements meas = DrawMeasurements(run, true, rng);
    SmallProblem sp;
    BuildProblem(reg, "left", method, PreintegrationFactorOptions{}, run, meas, sp);
    ::ceres::Solver::Options so = TightSolverOptions();
    so.function_tolerance = 1e-12;  // the errors compared are of the order of the noise
    ::ceres::Solver::Summary summary;
    ::ceres::Solve(so, sp.problem.get(), &summary);
    ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();

    // One keyframe per run (they take turns), whose 6 bias components are one Gaussian vector
    // of the run: the runs are independent, so the counts and sums below are of independent
    // variables, as the binomial and chi-square laws assume.
    const int k = run_index % kKeyframes;
    double* block = sp.blocks[k].data();
    ::ceres::Covariance::Options co;
    co.algorithm_type = ::ceres::DENSE_SVD;
    ::ceres::Covariance covariance(co);
    const std::vector<std::pair<const double*, const double*>> wanted{{block, block}};
    ASSERT_TRUE(covariance.Compute(wanted, sp.problem.get()));
    Eigen::Matrix<double, 15, 15, Eigen::RowMajor> C;
    ASSERT_TRUE(covariance.GetCovarianceBlockInTangentSpace(block, block, C.data()));
    const ImuState est = FromStateBlock(block);
    Eigen::Matrix<double, 6, 1> e;
    e << est.bg - run.truth[k].bg, est.ba - run.truth[k].ba;
    Eigen::Matrix<double, 6, 6> Cb;
    Cb << C.block<3, 3>(bg_at, bg_at), C.block<3, 3>(bg_at, ba_at), C.block<3, 3>(ba_at, bg_at),
        C.block<3, 3>(ba_at, ba_at);
    sum_nees += e.dot(Cb.ldlt().solve(e));
    // One component per run (they take turns too) for the 3-sigma count and the mean square,
    // so that the counted events are independent Bernoulli trials.
    const int c = (run_index / kKeyframes) % 6;
    const double z = e[c] / std::sqrt(Cb(c, c));
    sum_z2 += z * z;
    if (std::abs(z) > 3.0) ++outside_3_sigma;
  }
  // Design false-alarm rate of each check: 1e-3 (two-sided for the chi-square ones), so that a
  // correct implementation fails one of the three in well under 1% of seeds; the seed is fixed.
  constexpr double kFalseAlarm = 1e-3;
  constexpr double kOutsideRate = 1.0 - 0.9973;  // Gaussian Pr(|z| > 3)
  int allowed = 0;
  while (BinomialUpperTail(kRuns, kOutsideRate, allowed) > kFalseAlarm) ++allowed;
  EXPECT_LE(outside_3_sigma, allowed)
      << "components outside 3 sigma in " << kRuns << " runs (a Gaussian: " << kOutsideRate * kRuns
      << " expected)";
  const double z2_lo = ChiSquareQuantileExact(kRuns, kFalseAlarm / 2) / kRuns;
  const double z2_hi = ChiSquareQuantileExact(kRuns, 1 - kFalseAlarm / 2) / kRuns;
  EXPECT_GT(sum_z2 / kRuns, z2_lo);
  EXPECT_LT(sum_z2 / kRuns, z2_hi);
  const double nees_lo = ChiSquareQuantileExact(6.0 * kRuns, kFalseAlarm / 2) / kRuns;
  const double nees_hi = ChiSquareQuantileExact(6.0 * kRuns, 1 - kFalseAlarm / 2) / kRuns;
  EXPECT_GT(sum_nees / kRuns, nees_lo);
  EXPECT_LT(sum_nees / kRuns, nees_hi);
  std::printf(
      "bias consistency: %d of %d components outside 3 sigma (allowed %d); mean z^2 %.3f in "
      "[%.3f, %.3f]; mean 6-dof NEES %.3f in [%.3f, %.3f]\n",
      outside_3_sigma, kRuns, allowed, sum_z2 / kRuns, z2_lo, z2_hi, sum_nees / kRuns, nees_lo,
      nees_hi);
}

}  // namespace
}  // namespace imuconv::ceres_test
