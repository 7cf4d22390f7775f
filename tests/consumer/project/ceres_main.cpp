// Links the installed imuconv::ceres (when the package was built with it): a one-keyframe
// problem, a pose measurement through the `gtsam_navstate` manifold, solved to the measurement.
#include <ceres/ceres.h>
#include <imuconv/ceres/pose_factors.h>
#include <imuconv/ceres/state_block.h>
#include <imuconv/ceres/state_manifold.h>
#include <imuconv/so3.h>

#include <array>
#include <cstdio>

int main() {
  using namespace imuconv;
  using namespace imuconv::ceres_factors;
  Registry reg;
  for (const auto& issue : reg.load_search_path())
    std::fprintf(stderr, "%s: %s\n", issue.file.c_str(), issue.message.c_str());
  const Mat3 R_meas = so3::Exp(Vec3(0.3, -0.2, 0.5));
  const Vec3 p_meas(1.0, 2.0, 3.0);
  std::array<double, kStateBlockSize> block;
  ToStateBlock(ImuState{}, block.data());
  ceres::Problem problem;
  problem.AddParameterBlock(block.data(), kStateBlockSize,
                            new StateManifold(reg, "gtsam_navstate"));
  problem.AddResidualBlock(MakePoseMeasurement(R_meas, p_meas, 0.01, 0.01), nullptr, block.data());
  ceres::Solver::Options options;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  const ImuState x = FromStateBlock(block.data());
  // A pose measurement alone: the optimum is the measurement, to the solver's tolerance.
  const double e =
      std::max((x.R - R_meas).cwiseAbs().maxCoeff(), (x.p - p_meas).cwiseAbs().maxCoeff());
  std::printf("imuconv::ceres: pose error %.2e after %d iterations\n", e,
              static_cast<int>(summary.iterations.size()));
  return e < 1e-6 ? 0 : 1;
}
