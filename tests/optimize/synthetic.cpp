// imuconv optimize on noise-free synthetic data with known constant biases: the estimate must be
// the truth but for the one cost that is not zero there, the weak prior on the first keyframe,
// whose pull is bounded from the reported covariances.
#include <gtest/gtest.h>

#include <cmath>

#include "../bridge/synthetic.h"
#include "../support/imuconv_test.h"
#include "imuconv/bridge.h"
#include "imuconv/optimize/optimize.h"
#include "imuconv/prediction.h"
#include "imuconv/so3.h"

namespace {

using namespace imuconv;
using imuconv::test::Plugins;

// Truth: 3 s of the smooth sequence at 200 Hz, the states at every sample chained by the
// method's own one-interval preintegration and the prediction (the note, section 3.2): a
// preintegration over many intervals is the composition of one-interval ones (GTSAM's update is
// that composition), so the truth satisfies every factor of any keyframe spacing exactly, up to
// rounding.
struct Synthetic {
  pipeline::ImuData imu;
  pipeline::GroundTruth truth;
  Vec3 bg = Vec3(0.01, -0.02, 0.015), ba = Vec3(0.05, 0.1, -0.08);
  ImuNoise noise{1.7e-4, 2.0e-3, 1.9e-5, 3.0e-3};  // EuRoC's datasheet densities
  Vec3 g = Vec3(0, 0, -9.81);

  explicit Synthetic(const std::string& method_id) {
    const Registry& reg = Plugins();
    imu.samples = test::SmoothImu(3.0, 200.0, 0.0);
    imu.source = "synthetic";
    const PreintegrationMethod method =
        ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, method_id);
    ImuState x;
    x.R = so3::Exp(Vec3(0.3, -1.1, 0.7));
    x.p = Vec3(3, -2, 1);
    x.v = Vec3(0.5, 1.5, -0.2);
    x.bg = bg;
    x.ba = ba;
    truth.source = "synthetic truth";
    truth.full_state = true;
    for (std::size_t k = 0; k < imu.samples.size(); ++k) {
      truth.t.push_back(imu.samples[k].t);
      truth.x.push_back(x);
      if (k + 1 == imu.samples.size()) break;
      SampleWindow w;
      EXPECT_TRUE(MakeWindow(imu.samples.data(), imu.samples.size(), imu.samples[k].t,
                             imu.samples[k + 1].t, w)
                      .ok());
      const Preintegrated m = Preintegrate(reg, method, w, bg, ba, noise);
      x = Predict(x, m.delta, m.dt, g);
    }
  }
};

TEST(OptimizeSynthetic, RecoversKnownBiasesFromNoiseFreeData) {
  const Synthetic s("manifold");
  optimize::Options o;
  o.method = "manifold";
  o.keyframe_step = 0.25;  // 50 intervals a factor, 13 keyframes
  o.noise = s.noise;
  o.gravity = s.g;
  o.pose_sigma_m = 1e-3;
  o.pose_sigma_rad = 1e-3;
  const optimize::Result r = optimize::RunOptimize(Plugins(), s.imu, s.truth, o);
  ASSERT_TRUE(r.converged) << r.solver_message;
  ASSERT_TRUE(r.covariance_ok) << r.covariance_message;
  ASSERT_EQ(r.keyframes.size(), 13u);
  // Linearized at zero bias, every factor's start bias moved by |bg| = 0.027 rad/s > 0.01 after
  // the first solve: all are re-integrated, and then none moves again.
  ASSERT_GE(r.rounds.size(), 2u);
  EXPECT_EQ(r.rounds[0].reintegrated, r.factors);
  EXPECT_EQ(r.pending_reintegration, 0);

  // The prior's pull, to first order: delta_k = Sigma_{k,0} Lambda_prior r_prior, where r_prior =
  // x_prior - x_true (left chart) is -b_true in the bias rows and the velocity's central
  // difference error in v (p and theta are exact). By Cauchy-Schwarz |Sigma_{k,0}(i, j)| <=
  // sigma_k(i) sigma_0(j), so |delta_k(i)| <= sigma_k(i) * sum_j sigma_0(j) |r_j| /
  // sigma_prior_j^2. The bias rows dominate that sum; the velocity rows are bounded by the central
  // difference's error, at most |a| step^2 / 24 with |a| < 20 m/s^2. Twice the first-order bound
  // covers the nonlinearity; 1e-9 the rounding of the chained truth.
  const optimize::WeakPriorSigmas prior;
  const auto& k0 = r.keyframes[0];
  auto block = [&](const char* label) {
    for (std::size_t b = 0; b < r.labels.size(); ++b)
      if (r.labels[b] == label) return static_cast<int>(3 * b);
    return -1;
  };
  const int og = block("bg"), oa = block("ba"), ov = block("v");
  double pull = 0.0;
  const double v_err = 20.0 * o.keyframe_step * o.keyframe_step / 24.0;
  for (int a = 0; a < 3; ++a) {
    pull +=
        std::sqrt(k0.cov(og + a, og + a)) * std::abs(s.bg[a]) / (prior.bg_radps * prior.bg_radps);
    pull += std::sqrt(k0.cov(oa + a, oa + a)) * std::abs(s.ba[a]) / (prior.ba_mps2 * prior.ba_mps2);
    pull += std::sqrt(k0.cov(ov + a, ov + a)) * v_err / (prior.v_mps * prior.v_mps);
  }
  for (const auto& k : r.keyframes)
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(k.x.bg[a], s.bg[a], 2 * std::sqrt(k.cov(og + a, og + a)) * pull + 1e-9)
          << "t " << k.t << " axis " << a;
      EXPECT_NEAR(k.x.ba[a], s.ba[a], 2 * std::sqrt(k.cov(oa + a, oa + a)) * pull + 1e-9)
          << "t " << k.t << " axis " << a;
    }
  // The bound is a real constraint: far below the biases themselves (1e-2).
  EXPECT_LT(2 * std::sqrt(k0.cov(og, og)) * pull, 1e-4);
}

}  // namespace
