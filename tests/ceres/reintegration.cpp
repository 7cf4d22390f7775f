// Re-integration (VINS-Fusion's repropagate): Reintegrate gives the measurement a fresh
// preintegration gives, ReintegrateIfMoved respects its thresholds, and the first-order bias
// correction it replaces differs from re-integration by O(|delta b|^2).
#include <gtest/gtest.h>

#include "ceres_problem.h"
#include "imuconv/window.h"
#include "imuconv_test.h"

namespace imuconv::ceres_test {
namespace {

using ReintegrationData = RunWithMethod;

ReintegrationData MakeData(const char* method_id, PluginKind kind) {
  std::mt19937 rng(99);
  ReintegrationData d;
  d.run = SimulateAtTypicalBiases(2, 0.5, 200.0, true, rng);
  d.method = ResolvePreintegrationMethod(test::Plugins(), kind, method_id);
  return d;
}

TEST(CeresReintegration, ReintegrateEqualsAFreshPreintegration) {
  const Registry& reg = test::Plugins();
  for (const auto& [kind, id] : {std::pair{PluginKind::Preintegrator, "manifold"},
                                 std::pair{PluginKind::Preintegrator, "vins_fusion"},
                                 std::pair{PluginKind::Propagator, "rk4"}}) {
    const ReintegrationData d = MakeData(id, kind);
    PreintegrationFactor factor(reg, d.method, d.run.samples, 0.0, 0.5, SimulatedNoise(),
                                Vec3::Zero(), Vec3::Zero());
    const Vec3 bg(0.012, -0.018, 0.02), ba(0.09, -0.06, 0.21);
    factor.Reintegrate(bg, ba);
    SampleWindow window;
    ASSERT_TRUE(MakeWindow(d.run.samples.data(), d.run.samples.size(), 0.0, 0.5, window));
    const Preintegrated fresh = Preintegrate(reg, d.method, window, bg, ba, SimulatedNoise());
    const Preintegrated& m = factor.measurement();
    // The same function on the same numbers: bit for bit.
    EXPECT_EQ(m.delta.dR, fresh.delta.dR) << id;
    EXPECT_EQ(m.delta.dp, fresh.delta.dp) << id;
    EXPECT_EQ(m.delta.dv, fresh.delta.dv) << id;
    EXPECT_EQ(m.cov, fresh.cov) << id;
    EXPECT_EQ(m.J_bias, fresh.J_bias) << id;
    EXPECT_EQ(m.bg_hat, bg) << id;
    EXPECT_EQ(m.ba_hat, ba) << id;
    EXPECT_TRUE(m.in_reference_charts()) << id;
    // The whitening follows the measurement: S cov(r) S^T = I at the new prediction.
    ImuState x_s;
    x_s.bg = bg;
    x_s.ba = ba;
    const ImuState x_e = Predict(x_s, m.delta, m.dt, factor.options().gravity);
    const Residual r = factor.Evaluate(x_s, x_e);
    // A 15x15 Cholesky solve of a covariance with condition number below 1e8: 1e-8 margin.
    EXPECT_LT((r.cov - Mat15::Identity()).cwiseAbs().maxCoeff(), 1e-8) << id;
  }
}

TEST(CeresReintegration, ReintegrateIfMovedRespectsTheThresholds) {
  const Registry& reg = test::Plugins();
  const ReintegrationData d = MakeData("manifold", PluginKind::Preintegrator);
  PreintegrationFactorOptions fo;
  fo.reintegrate_gyro_bias = 0.01;
  fo.reintegrate_accel_bias = 0.1;
  const Vec3 bg0(0.01, -0.02, 0.015), ba0(0.1, -0.05, 0.2);
  PreintegrationFactor factor(reg, d.method, d.run.samples, 0.0, 0.5, SimulatedNoise(), bg0, ba0,
                              fo);
  // Within both thresholds (norms 0.009 and 0.09): kept.
  EXPECT_FALSE(factor.ReintegrateIfMoved(bg0 + Vec3(0.009, 0, 0), ba0 + Vec3(0, 0.09, 0)));
  EXPECT_EQ(factor.measurement().bg_hat, bg0);
  // Exactly at a threshold is not beyond it. (0.5 and 0.25 and their sums are exact.)
  PreintegrationFactorOptions exact = fo;
  exact.reintegrate_gyro_bias = 0.5;
  PreintegrationFactor at_threshold(reg, d.method, d.run.samples, 0.0, 0.5, SimulatedNoise(),
                                    Vec3(0.25, 0, 0), Vec3::Zero(), exact);
  EXPECT_FALSE(at_threshold.ReintegrateIfMoved(Vec3(0.75, 0, 0), Vec3::Zero()));
  // The gyro bias beyond its threshold by norm (each component 0.006, norm 0.0104).
  const Vec3 bg1 = bg0 + Vec3::Constant(0.006);
  EXPECT_TRUE(factor.ReintegrateIfMoved(bg1, ba0));
  EXPECT_EQ(factor.measurement().bg_hat, bg1);
  // The accelerometer bias beyond its own threshold, the gyro bias unmoved.
  const Vec3 ba1 = ba0 + Vec3(0.0, 0.0, 0.11);
  EXPECT_TRUE(factor.ReintegrateIfMoved(bg1, ba1));
  EXPECT_EQ(factor.measurement().ba_hat, ba1);
  // Default thresholds (+infinity): never.
  PreintegrationFactor never(reg, d.method, d.run.samples, 0.0, 0.5, SimulatedNoise(), bg0, ba0);
  EXPECT_FALSE(never.ReintegrateIfMoved(bg0 + Vec3::Constant(1.0), ba0 + Vec3::Constant(10.0)));
  EXPECT_EQ(never.measurement().bg_hat, bg0);
}

// |r_first_order(b0 + s u) - r_reintegrated(b0 + s u)| for a bias step s along u, unwhitened.
double CorrectionError(const Registry& reg, const ReintegrationData& d, const Vec3& bg0,
                       const Vec3& ba0, double s) {
  const Vec3 ug(0.5, -0.3, 0.8), ua(3.0, 2.0, -4.0);  // rad/s and m/s^2 per unit step
  SampleWindow window;
  EXPECT_TRUE(MakeWindow(d.run.samples.data(), d.run.samples.size(), 0.0, 0.5, window));
  const Preintegrated at_b0 = Preintegrate(reg, d.method, window, bg0, ba0, SimulatedNoise());
  const Preintegrated at_b =
      Preintegrate(reg, d.method, window, bg0 + s * ug, ba0 + s * ua, SimulatedNoise());
  ImuState x_s = d.run.truth[0];
  x_s.bg = bg0 + s * ug;
  x_s.ba = ba0 + s * ua;
  const ImuState x_e = d.run.truth[1];
  const Vec15 r1 =
      ComputeResidual(reg, ResidualKind::Gtsam, at_b0, x_s, x_e, "left", kSimulatedGravity).r;
  const Vec15 r2 =
      ComputeResidual(reg, ResidualKind::Gtsam, at_b, x_s, x_e, "left", kSimulatedGravity).r;
  return (r1 - r2).head<9>().norm();
}

TEST(CeresReintegration, FirstOrderCorrectionErrsBySecondOrderInTheBiasStep) {
  const Registry& reg = test::Plugins();
  for (const auto& [kind, id] : {std::pair{PluginKind::Preintegrator, "manifold"},
                                 std::pair{PluginKind::Propagator, "rk4"}}) {
    const ReintegrationData d = MakeData(id, kind);
    const Vec3 bg0(0.01, -0.02, 0.015), ba0(0.1, -0.05, 0.2);
    const double s = 0.01;
    const double e1 = CorrectionError(reg, d, bg0, ba0, s);
    const double e2 = CorrectionError(reg, d, bg0, ba0, 2.0 * s);
    std::printf(
        "%s: first-order correction vs re-integration: %.3e at step %.2g, %.3e at %.2g, "
        "ratio %.3f\n",
        id, e1, s, e2, 2.0 * s, e2 / e1);
    // O(s^2): doubling the step quadruples the difference; the third-order term shifts the ratio
    // by O(s) relative, a few per cent at s = 0.01 (a 0.005 rad/s, 0.03 m/s^2 bias step), and
    // round-off (1e-15) is far below e1. A first-order error (a wrong bias Jacobian) gives 2.
    EXPECT_GT(e2 / e1, 3.6) << id;
    EXPECT_LT(e2 / e1, 4.4) << id;
    EXPECT_GT(e1, 1e-10) << id;  // measurably non-zero: the comparison is not of round-off
  }
}

}  // namespace
}  // namespace imuconv::ceres_test
