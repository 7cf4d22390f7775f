// The optimum does not depend on the state convention that parameterizes the problem
// (factors/README.md): the same small problem, solved with the manifold of every registered
// convention, reaches the same states.
#include <gtest/gtest.h>

#include "ceres_problem.h"
#include "imuconv_test.h"

namespace imuconv::ceres_test {
namespace {

TEST(CeresChartIndependence, SameOptimumInEveryStateConvention) {
  const Registry& reg = test::Plugins();
  const auto [run, meas, method] = MakeChartIndependenceData(reg);
  for (ResidualKind kind : {ResidualKind::Gtsam, ResidualKind::Forster}) {
    std::vector<ImuState> reference;  // the optimum with the `left` manifold
    std::string reference_id;
    for (const std::string& id : reg.ids(PluginKind::StateConvention)) {
      SmallProblem sp;
      PreintegrationFactorOptions fo;
      fo.kind = kind;
      BuildProblem(reg, id, method, fo, run, meas, sp);
      ::ceres::Solver::Summary summary;
      ::ceres::Solve(TightSolverOptions(), sp.problem.get(), &summary);
      ASSERT_TRUE(summary.IsSolutionUsable()) << id << ": " << summary.BriefReport();
      ASSERT_EQ(summary.termination_type, ::ceres::CONVERGENCE)
          << id << ": " << summary.BriefReport();
      const std::vector<ImuState> optimum = StatesOfBlocks(sp.blocks);
      if (reference.empty()) {
        reference = optimum;
        reference_id = id;
        continue;
      }
      // 1e-8 in the left chart's units (m, rad, m/s, rad/s, m/s^2): the solver stops where the
      // relative cost change is below 1e-16 or the gradient below 1e-14, and the problem's
      // Hessian is well conditioned (whitened by sigmas of 1e-3 to 1e-1), so two optima agree to
      // about 1e-10; a convention-dependent cost would move them by a fraction of the noise
      // (1e-3 and more).
      for (std::size_t k = 0; k < optimum.size(); ++k) {
        Vec15 d;
        LeftLocal(reference[k], optimum[k], d);
        EXPECT_LT(d.cwiseAbs().maxCoeff(), 1e-8)
            << "keyframe " << k << ": " << id << " vs " << reference_id << ", residual kind "
            << static_cast<int>(kind);
      }
    }
  }
}

}  // namespace
}  // namespace imuconv::ceres_test
