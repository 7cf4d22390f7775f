// Every residual plugin's cost (NativeResidualFactor): its Jacobians against central differences
// along Ceres's own path (jacobian_check.h), with every registered state convention as the
// manifold.
#include <gtest/gtest.h>

#include "imuconv_test.h"
#include "jacobian_check.h"
#include "native_problem.h"

namespace imuconv::ceres_test {
namespace {

// Central differences with h = 1e-6 of whitened residuals, as cost_jacobians.cpp: truncation
// O(h^2 r''') and round-off 1e-16 |r| / h, about 1e-6 of the largest entry at worst; a wrong
// block, sign or column order is O(1) of it.
constexpr double kNativeJacobianTol = 1e-5;

// ORB-SLAM3 reads the start biases into IMU::Bias in float, and its first-order deltas are
// float (orb_slam3.cpp): along a bias column the residual moves in float steps (6e-8 of
// |dV|, |dP|), so a step of 1e-6 would see rounding of 6e-8 x |dV| / 2e-6, a few percent of an
// entry. Those columns are differenced with h = 1e-2 instead, as
// tests/pipeline/residual_plugin_jacobians.cpp does for the plugin's own Jacobians: rounding
// 6e-8 x 5 / 2e-2 = 1.5e-5 of an entry and a truncation error near h^2 |JRg|^3 (below 1e-4
// for a 0.2 s interval, |JRg| <= 0.2): held to 1e-3 of the block's largest entry, still far
// below a wrong block or sign (O(1)). Its pose and velocity columns are double arithmetic on
// the float deltas (constants of the measurement): the same 1e-5 as the others.
constexpr double kFloatBiasStep = 1e-2, kFloatBiasTol = 1e-3;

TEST(NativeResidualCostJacobians, EveryResidualPluginInEveryStateConvention) {
  const Registry& reg = test::Plugins();
  const std::vector<std::string> residuals = reg.ids(PluginKind::Residual);
  ASSERT_FALSE(residuals.empty()) << "no residual plugin in the build's plugin directory";
  std::mt19937 rng(11);
  const SimulatedRun run = SimulateAtTypicalBiases(3, 0.2, 200.0, true, rng);
  const PreintegrationMethod method =
      ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, "manifold");
  for (const std::string& id : residuals) {
    const NativeResidualFactor factor(reg, id, method, run.samples, run.keyframe_t[1],
                                      run.keyframe_t[2], SimulatedNoise(), run.truth[1].bg,
                                      run.truth[1].ba);
    std::unique_ptr<::ceres::CostFunction> cost(factor.MakeCostFunction());
    ASSERT_EQ(cost->num_residuals(), reg.info(PluginKind::Residual, id).degrees_of_freedom) << id;
    // States off the prediction, with the start biases at the measurement's linearization bias:
    // there every system's bias Jacobians are derivatives of its residual (away from it they
    // are its own first-order model: the kernels' headers).
    ImuState x_s = Perturbed(run.truth[1], 1), x_e = Perturbed(run.truth[2], 2);
    x_s.bg = factor.preintegration().measurement().bg_hat;
    x_s.ba = factor.preintegration().measurement().ba_hat;
    std::array<double, kStateBlockSize> bs, be;
    ToStateBlock(x_s, bs.data());
    ToStateBlock(x_e, be.data());
    Eigen::VectorXd r(cost->num_residuals());
    double* blocks[] = {bs.data(), be.data()};
    ASSERT_TRUE(cost->Evaluate(blocks, r.data(), nullptr)) << id;
    ASSERT_GT(r.norm(), 1.0) << id << ": the states should be off the prediction";
    for (const std::string& conv : reg.ids(PluginKind::StateConvention)) {
      const StateManifold M(reg, conv);
      const BlockLabels labels = reg.state_convention(conv)->labels();
      Eigen::VectorXd steps = Eigen::VectorXd::Constant(15, 1e-6);
      std::vector<int> bias_columns;
      for (const char* b : {"bg", "ba"})
        for (int i = 0; i < 3; ++i) bias_columns.push_back(BlockOffset(labels, b) + i);
      if (ReadsInFloat(id))
        for (int c : bias_columns) steps[c] = kFloatBiasStep;
      const std::vector<Eigen::VectorXd> err =
          TangentJacobianColumnErrors(*cost, {bs.data(), be.data()}, {&M, &M}, {steps, steps});
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 15; ++c) {
          const bool bias =
              std::find(bias_columns.begin(), bias_columns.end(), c) != bias_columns.end();
          const double tol = bias && ReadsInFloat(id) ? kFloatBiasTol : kNativeJacobianTol;
          EXPECT_LT(err[b][c], tol)
              << id << ", convention " << conv << ", " << (b == 0 ? "start" : "end")
              << " state, tangent column " << c << " (" << labels[c / 3] << ")";
        }
    }
  }
}

}  // namespace
}  // namespace imuconv::ceres_test
