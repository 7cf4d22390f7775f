// Every cost's Jacobian against central differences along Ceres's own path (cost ambient
// Jacobian x PlusJacobian vs differences of the cost through Plus), in every registered state
// convention, for both residual kinds.
#include <gtest/gtest.h>

#include "ceres_problem.h"
#include "imuconv_test.h"
#include "jacobian_check.h"

namespace imuconv::ceres_test {
namespace {

// Central differences with h = 1e-6 (jacobian_check.h) of whitened residuals: truncation
// O(h^2 r''') and round-off 1e-16 |r| / h, with |r| up to 1e4 at the states below, about 1e-6
// of the largest entry at worst; a wrong block or sign is O(1) of it.
constexpr double kJacobianTol = 1e-5;

// Two states about a keyframe interval apart, off the measurement's prediction and off its
// linearization bias, so that every term of the residual and its bias correction is non-zero.
void StatesAround(const SimulatedRun& run, ImuState& x_s, ImuState& x_e) {
  x_s = Perturbed(run.truth[1], 1);
  x_e = Perturbed(run.truth[2], 2);
  x_s.bg += Vec3(0.004, -0.003, 0.002);
  x_s.ba += Vec3(0.03, 0.02, -0.04);
}

TEST(CeresCostJacobians, PreintegrationFactorInEveryConventionAndResidualKind) {
  const Registry& reg = test::Plugins();
  std::mt19937 rng(11);
  const SimulatedRun run = SimulateAtTypicalBiases(3, 0.2, 200.0, true, rng);
  for (const auto& [kind_id, kind] : {std::pair{PluginKind::Preintegrator, "manifold"},
                                      std::pair{PluginKind::Propagator, "rk4"}}) {
    const PreintegrationMethod method = ResolvePreintegrationMethod(reg, kind_id, kind);
    for (ResidualKind rk : {ResidualKind::Gtsam, ResidualKind::Forster}) {
      PreintegrationFactorOptions fo;
      fo.kind = rk;
      const PreintegrationFactor factor(reg, method, run.samples, run.keyframe_t[1],
                                        run.keyframe_t[2], SimulatedNoise(), run.truth[1].bg,
                                        run.truth[1].ba, fo);
      std::unique_ptr<::ceres::CostFunction> cost(factor.MakeCostFunction());
      ImuState x_s, x_e;
      StatesAround(run, x_s, x_e);
      std::array<double, kStateBlockSize> bs, be;
      ToStateBlock(x_s, bs.data());
      ToStateBlock(x_e, be.data());
      for (const std::string& id : reg.ids(PluginKind::StateConvention)) {
        const StateManifold M(reg, id);
        const double err = TangentJacobianError(*cost, {bs.data(), be.data()}, {&M, &M});
        EXPECT_LT(err, kJacobianTol)
            << kind << ", residual kind " << static_cast<int>(rk) << ", convention " << id;
      }
    }
  }
}

TEST(CeresCostJacobians, PriorInEveryConventionUnderEveryManifold) {
  const Registry& reg = test::Plugins();
  const std::vector<ImuState> xs = test::TestStates();
  ImuState prior = xs[2];
  ImuState x = prior;
  x.R = so3::Exp(Vec3(0.2, -0.1, 0.3)) * prior.R;
  x.p += Vec3(0.5, -0.2, 0.1);
  x.v += Vec3(0.1, 0.1, -0.2);
  x.bg += Vec3(0.01, 0.0, -0.01);
  x.ba += Vec3(0.0, 0.05, 0.02);
  Vec15 sd;
  for (int i = 0; i < 15; ++i) sd[i] = 0.05 + 0.01 * i;
  const Mat15 cov = sd.cwiseAbs2().asDiagonal();
  std::array<double, kStateBlockSize> b;
  ToStateBlock(x, b.data());
  for (const std::string& prior_chart : reg.ids(PluginKind::StateConvention)) {
    std::unique_ptr<::ceres::CostFunction> cost(MakeStatePrior(reg, prior_chart, prior, cov));
    for (const std::string& id : reg.ids(PluginKind::StateConvention)) {
      const StateManifold M(reg, id);
      EXPECT_LT(TangentJacobianError(*cost, {b.data()}, {&M}), kJacobianTol)
          << "prior in " << prior_chart << ", manifold " << id;
    }
  }
}

TEST(CeresCostJacobians, PoseMeasurementUnderEveryManifold) {
  const Registry& reg = test::Plugins();
  for (const ImuState& x : test::TestStates()) {
    std::unique_ptr<::ceres::CostFunction> cost(MakePoseMeasurement(
        so3::Exp(Vec3(0.3, 0.1, -0.2)) * x.R, x.p + Vec3(0.1, -0.3, 0.2), 0.05, 0.02));
    std::array<double, kStateBlockSize> b;
    ToStateBlock(x, b.data());
    for (const std::string& id : reg.ids(PluginKind::StateConvention)) {
      const StateManifold M(reg, id);
      EXPECT_LT(TangentJacobianError(*cost, {b.data()}, {&M}), kJacobianTol) << id;
    }
  }
}

}  // namespace
}  // namespace imuconv::ceres_test
