// What the tests of NativeResidualFactor share: the residual plugins of the build, a factor of
// each on the simulated run of ceres_problem.h (test::KeepingResidualSink keeps what a plugin
// writes), and the small problem of ceres_problem.h with native factors in place of the
// registry's residuals.
#pragma once

#include <ceres/ceres.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ceres_problem.h"
#include "imuconv/ceres/native_residual_factor.h"
#include "imuconv/residual_factor.h"
#include "keeping_residual_sink.h"

namespace imuconv::ceres_test {

/// The residual plugins whose system holds its preintegration in float and reads the start
/// biases in float (ORB-SLAM3, plugins/residuals/orb_slam3.cpp): their residual is a function of
/// the states in double arithmetic but a staircase in the start biases, which the tests allow
/// for where they say so.
inline bool ReadsInFloat(const std::string& residual_id) { return residual_id == "orb_slam3"; }

/// A bias random-walk term between two keyframes, r = [(bg_1 - bg_0) / s_g; (ba_1 - ba_0) / s_a]
/// with s = sigma_w sqrt(dt): what Basalt and ORB-SLAM3 add beside their 9-dimensional factors
/// (the end biases are otherwise unconstrained). Linear in the blocks' bias entries.
class BiasWalkCost final : public ::ceres::SizedCostFunction<6, kStateBlockSize, kStateBlockSize> {
 public:
  BiasWalkCost(double dt, const ImuNoise& n)
      : wg_(1.0 / (n.gyro_random_walk * std::sqrt(dt))),
        wa_(1.0 / (n.accel_random_walk * std::sqrt(dt))) {}
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    for (int i = 0; i < 3; ++i) {
      r[i] = wg_ * (x[1][block_idx::bg + i] - x[0][block_idx::bg + i]);
      r[3 + i] = wa_ * (x[1][block_idx::ba + i] - x[0][block_idx::ba + i]);
    }
    for (int b = 0; b < 2; ++b) {
      if (J == nullptr || J[b] == nullptr) continue;
      const double sign = b == 0 ? -1.0 : 1.0;
      std::fill(J[b], J[b] + 6 * kStateBlockSize, 0.0);
      for (int i = 0; i < 3; ++i) {
        J[b][i * kStateBlockSize + block_idx::bg + i] = sign * wg_;
        J[b][(3 + i) * kStateBlockSize + block_idx::ba + i] = sign * wa_;
      }
    }
    return true;
  }

 private:
  double wg_, wa_;
};

/// ceres_problem.h's SmallProblem with one NativeResidualFactor `id` per keyframe pair (and, for
/// a residual without bias-walk rows, a BiasWalkCost beside it).
struct NativeProblem {
  std::vector<std::unique_ptr<NativeResidualFactor>> factors;
  std::vector<std::array<double, kStateBlockSize>> blocks;
  std::unique_ptr<::ceres::Problem> problem;
};

inline void BuildNativeProblem(const Registry& reg, const std::string& convention,
                               const std::string& id, const PreintegrationMethod& method,
                               const SimulatedRun& run, const Measurements& meas,
                               NativeProblem& out) {
  out.problem = NewProblemOfPosesAndPrior(reg, convention, run, meas, out.blocks);
  for (std::size_t k = 0; k + 1 < run.truth.size(); ++k) {
    out.factors.push_back(std::make_unique<NativeResidualFactor>(
        reg, id, method, run.samples, run.keyframe_t[k], run.keyframe_t[k + 1], SimulatedNoise(),
        meas.prior.bg, meas.prior.ba));
    out.problem->AddResidualBlock(out.factors.back()->MakeCostFunction(), nullptr,
                                  out.blocks[k].data(), out.blocks[k + 1].data());
    if (out.factors.back()->dimension() < 15)
      out.problem->AddResidualBlock(
          new BiasWalkCost(run.keyframe_t[k + 1] - run.keyframe_t[k], SimulatedNoise()), nullptr,
          out.blocks[k].data(), out.blocks[k + 1].data());
  }
}

}  // namespace imuconv::ceres_test
