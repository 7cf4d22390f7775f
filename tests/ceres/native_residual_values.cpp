// What a NativeResidualFactor evaluates is the system's own factor: its unwhitened residual is
// the plugin's `residual` output for the same measurement and states (the output the anchors
// tie to each system's numbers, tests/reference/*residual*, *anchor*), its squared whitened
// residual is the system's own squared distance (VINS-Fusion's |sqrt_info r|^2, Basalt's
// r^T cov^-1 r, OKVIS2's r^T information r, ORB-SLAM3's chi2), and re-integration gives the
// factor a fresh one would have.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cstdio>
#include <limits>

#include "imuconv/window.h"
#include "imuconv_test.h"
#include "native_problem.h"

namespace imuconv::ceres_test {
namespace {

using NativeValuesSetup = RunWithMethod;

NativeValuesSetup MakeNativeValuesSetup() {
  std::mt19937 rng(5);
  NativeValuesSetup s;
  s.run = SimulateAtTypicalBiases(3, 0.2, 200.0, true, rng);
  s.method = ResolvePreintegrationMethod(test::Plugins(), PluginKind::Preintegrator, "manifold");
  return s;
}

TEST(NativeResidualCostValues, ResidualIsThePluginsOwnAndItsSquareTheSystemsDistance) {
  const Registry& reg = test::Plugins();
  const NativeValuesSetup s = MakeNativeValuesSetup();
  const double t_s = s.run.keyframe_t[1], t_e = s.run.keyframe_t[2];
  const Vec3 bg = s.run.truth[1].bg, ba = s.run.truth[1].ba;
  // The plugin's input built here, independently of the factor: the measurement preintegrated
  // and expressed in the plugin's increment convention by the registry.
  SampleWindow window;
  ASSERT_TRUE(MakeWindow(s.run.samples.data(), s.run.samples.size(), t_s, t_e, window).ok());
  const Preintegrated m = Preintegrate(reg, s.method, window, bg, ba, SimulatedNoise());
  // States off the prediction and off the linearization bias: every term is non-zero, the
  // bias correction included.
  ImuState x_s = Perturbed(s.run.truth[1], 1), x_e = Perturbed(s.run.truth[2], 2);
  for (const std::string& id : reg.ids(PluginKind::Residual)) {
    const NativeResidualFactor factor(reg, id, s.method, s.run.samples, t_s, t_e, SimulatedNoise(),
                                      bg, ba);
    const std::shared_ptr<const ResidualFactor> plugin = reg.residual_factor(id);
    const Preintegrated expressed =
        Express(reg, m, reg.info(PluginKind::Residual, id).native_convention);
    test::KeepingResidualSink sink;
    ASSERT_TRUE(plugin->evaluate(expressed, x_s, x_e, kSimulatedGravity, sink).ok()) << id;
    const Eigen::VectorXd own = sink.values.at(plugin->cost_spec()->residual);

    const NativeResidualFactor::Evaluation e = factor.Evaluate(x_s, x_e);
    ASSERT_EQ(e.residual.size(), own.size()) << id;
    // The same function of the same numbers (the measurement is Preintegrate's and Express's
    // in both, deterministic): equal to round-off, here bit for bit.
    EXPECT_EQ((e.residual - own).cwiseAbs().maxCoeff(), 0.0)
        << id << "\ncost's\n"
        << e.residual.transpose() << "\nplugin's\n"
        << own.transpose();

    // |S r|^2 against the system's own distance: the same quadratic form, computed through a
    // different factorization (an eigen-decomposition, a Cholesky factor, an LDLT solve), so
    // they agree to the round-off of the weighting's condition number kappa: 64 eps kappa.
    ASSERT_GE(sink.mahalanobis, 0.0) << id << " wrote no squared distance";
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(factor.sqrt_information());
    const double sigma_max = svd.singularValues()(0);
    const double sigma_min = svd.singularValues()(svd.singularValues().size() - 1);
    const double kappa = (sigma_max / sigma_min) * (sigma_max / sigma_min);
    const double tol = 64.0 * std::numeric_limits<double>::epsilon() * kappa;
    std::printf("  %-12s |S r|^2 = %.17g, the system's %.17g (relative %.2g, bound %.2g)\n",
                id.c_str(), e.whitened.squaredNorm(), sink.mahalanobis,
                std::abs(e.whitened.squaredNorm() - sink.mahalanobis) / sink.mahalanobis, tol);
    EXPECT_LE(std::abs(e.whitened.squaredNorm() - sink.mahalanobis) / sink.mahalanobis, tol)
        << id << ": |S r|^2 = " << e.whitened.squaredNorm()
        << ", the system's = " << sink.mahalanobis << " (kappa " << kappa << ")";
    EXPECT_GT(sink.mahalanobis, 1.0) << id;  // the states are off: a distance far from 0
  }
}

TEST(NativeResidualCostValues, ReintegrationGivesTheFactorAFreshOneHas) {
  const Registry& reg = test::Plugins();
  const NativeValuesSetup s = MakeNativeValuesSetup();
  const double t_s = s.run.keyframe_t[0], t_e = s.run.keyframe_t[1];
  const Vec3 bg0 = s.run.truth[0].bg, ba0 = s.run.truth[0].ba;
  const Vec3 bg1 = bg0 + Vec3(2e-3, -1e-3, 1e-3), ba1 = ba0 + Vec3(0.02, 0.01, -0.03);
  PreintegrationFactorOptions fo;
  fo.reintegrate_gyro_bias = 1e-3;  // rad/s: bg1 moved by 2.4e-3, beyond it
  for (const std::string& id : reg.ids(PluginKind::Residual)) {
    NativeResidualFactor factor(reg, id, s.method, s.run.samples, t_s, t_e, SimulatedNoise(), bg0,
                                ba0, fo);
    EXPECT_FALSE(factor.ReintegrateIfMoved(bg0 + Vec3(5e-4, 0.0, 0.0), ba0)) << id;
    ASSERT_TRUE(factor.ReintegrateIfMoved(bg1, ba1)) << id;
    const NativeResidualFactor fresh(reg, id, s.method, s.run.samples, t_s, t_e, SimulatedNoise(),
                                     bg1, ba1, fo);
    // Bit for bit: the same computation on the same numbers.
    EXPECT_EQ(factor.sqrt_information(), fresh.sqrt_information()) << id;
    EXPECT_EQ(factor.expressed_measurement().delta.dR, fresh.expressed_measurement().delta.dR);
    EXPECT_EQ(factor.expressed_measurement().cov, fresh.expressed_measurement().cov) << id;
    const ImuState x_s = Perturbed(s.run.truth[0], 0), x_e = Perturbed(s.run.truth[1], 1);
    EXPECT_EQ(factor.Evaluate(x_s, x_e).whitened, fresh.Evaluate(x_s, x_e).whitened) << id;
  }
}

}  // namespace
}  // namespace imuconv::ceres_test
