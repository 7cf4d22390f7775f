// Any propagator works: the factor built from a propagator (preintegration by propagation,
// rk4) and from native preintegrators (manifold, vins_fusion) on the same samples gives the same
// residual and Jacobians up to the schemes' own difference, which shrinks with the sample
// interval at the order of the less accurate scheme.
#include <gtest/gtest.h>

#include "ceres_problem.h"
#include "imuconv_test.h"

namespace imuconv::ceres_test {
namespace {

struct Difference {
  double residual = 0.0, jacobian = 0.0;
};

// Unwhitened residuals and Jacobians of two methods' factors at the true states of a noise-free
// run sampled at rate_hz; the Jacobians' difference relative to their largest entry.
Difference Between(const char* a, PluginKind ka, const char* b, PluginKind kb, double rate_hz) {
  const Registry& reg = test::Plugins();
  std::mt19937 rng(1);
  const SimulatedRun run = SimulateAtTypicalBiases(2, 0.5, rate_hz, false, rng);
  Residual r[2];
  int i = 0;
  for (const auto& [kind, id] : {std::pair{ka, a}, std::pair{kb, b}}) {
    const PreintegrationFactor f(reg, ResolvePreintegrationMethod(reg, kind, id), run.samples, 0.0,
                                 0.5, SimulatedNoise(), run.truth[0].bg, run.truth[0].ba);
    r[i++] = ComputeResidual(reg, ResidualKind::Gtsam, f.measurement(), run.truth[0], run.truth[1],
                             "left", kSimulatedGravity);
  }
  Difference d;
  d.residual = (r[0].r - r[1].r).cwiseAbs().maxCoeff();
  const double scale = std::max(r[0].H_start.cwiseAbs().maxCoeff(), 1.0);
  d.jacobian = std::max((r[0].H_start - r[1].H_start).cwiseAbs().maxCoeff(),
                        (r[0].H_end - r[1].H_end).cwiseAbs().maxCoeff()) /
               scale;
  return d;
}

TEST(CeresPropagators, ThePreintegratorOfTheSimulationLeavesNoResidual) {
  // The simulated truth is the forward-Euler recursion (ceres_problem.h), which `manifold`
  // integrates: its residual at the truth of a noise-free run is round-off of sums of 100
  // steps of O(10) numbers (1e-13), not a discretization error (1e-4 and more).
  const Registry& reg = test::Plugins();
  std::mt19937 rng(1);
  const SimulatedRun run = SimulateAtTypicalBiases(2, 0.5, 200.0, false, rng);
  const PreintegrationFactor f(
      reg, ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, "manifold"), run.samples,
      0.0, 0.5, SimulatedNoise(), run.truth[0].bg, run.truth[0].ba);
  const Residual r = ComputeResidual(reg, ResidualKind::Gtsam, f.measurement(), run.truth[0],
                                     run.truth[1], "left", kSimulatedGravity);
  EXPECT_LT(r.r.cwiseAbs().maxCoeff(), 1e-11);
}

TEST(CeresPropagators, PropagatorAndPreintegratorFactorsAgreeToTheSchemesDifference) {
  constexpr PluginKind P = PluginKind::Propagator, N = PluginKind::Preintegrator;
  const struct {
    const char *a, *b;
    PluginKind ka, kb;
    double order;  // of the difference of the two schemes in the sample interval h
  } kPairs[] = {
      {"rk4", "manifold", P, N, 1.0},     // forward Euler (zero-order hold) is first order
      {"rk4", "vins_fusion", P, N, 2.0},  // VINS-Fusion's midpoint is second order
  };
  for (const auto& p : kPairs) {
    const Difference coarse = Between(p.a, p.ka, p.b, p.kb, 200.0);
    const Difference fine = Between(p.a, p.ka, p.b, p.kb, 400.0);
    const double expected = std::pow(2.0, p.order);
    std::printf(
        "%s vs %s: residual %.3e at 200 Hz, %.3e at 400 Hz (ratio %.2f); Jacobians "
        "%.3e, %.3e (ratio %.2f)\n",
        p.a, p.b, coarse.residual, fine.residual, coarse.residual / fine.residual, coarse.jacobian,
        fine.jacobian, coarse.jacobian / fine.jacobian);
    // Halving h divides the schemes' difference by 2^order; the next order's term moves the
    // ratio by O(h |rate|) relative (h |omega| < 0.005 here), 20% allows for it and for the
    // run's different sampling of the same motion.
    EXPECT_GT(coarse.residual / fine.residual, 0.8 * expected) << p.a << " vs " << p.b;
    EXPECT_LT(coarse.residual / fine.residual, 1.2 * expected) << p.a << " vs " << p.b;
    // The Jacobians differ at first order in h for both pairs (measured: ratio 2.00): their
    // bias-Jacobian blocks come from each scheme's own first-order recursion of d(increment)/db,
    // not from the increment itself. Halving h halves it, within the same 20%; at 200 Hz over
    // 0.5 s it is below 1e-2 of their largest entry (h |omega| < 4e-3 per step).
    EXPECT_LT(coarse.jacobian, 1e-2) << p.a << " vs " << p.b;
    EXPECT_GT(coarse.jacobian / fine.jacobian, 0.8 * 2.0) << p.a << " vs " << p.b;
    EXPECT_LT(coarse.jacobian / fine.jacobian, 1.2 * 2.0) << p.a << " vs " << p.b;
  }
}

}  // namespace
}  // namespace imuconv::ceres_test
