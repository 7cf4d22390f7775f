// The estimated biases are consistent with their reported covariance: over noisy synthetic runs
// whose noise is exactly the declared model (white sample noise of the declared densities, a
// bias random walk of the declared densities, pose noise of the declared sigmas), each bias
// component's error over its reported sigma is standard normal, so the mean of its square is 1.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "../bridge/synthetic.h"
#include "../support/imuconv_test.h"
#include "imuconv/bridge.h"
#include "imuconv/optimize/optimize.h"
#include "imuconv/prediction.h"
#include "imuconv/so3.h"

namespace {

using namespace imuconv;
using imuconv::test::Plugins;

constexpr int kRuns = 100;

TEST(OptimizeMonteCarlo, BiasErrorsMatchTheirReportedCovariance) {
  const Registry& reg = Plugins();
  const PreintegrationMethod method =
      ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, "manifold");
  // The true motion: 1 s of the smooth sequence, its offsets taken as part of the motion.
  const std::vector<ImuSample> motion = test::SmoothImu(1.0, 200.0, 0.0);
  const ImuNoise noise{1.7e-4, 2.0e-3, 1.9e-5, 3.0e-3};  // EuRoC's datasheet densities
  const Vec3 g(0, 0, -9.81);
  const double dt = motion[1].t - motion[0].t;
  optimize::Options o;
  o.keyframe_step = 0.25;
  o.noise = noise;
  o.gravity = g;
  o.pose_sigma_m = 1e-3;
  o.pose_sigma_rad = 1e-3;
  std::mt19937 rng(20261127);
  std::normal_distribution<double> n01(0.0, 1.0);
  auto normal3 = [&](double s) { return Vec3(s * n01(rng), s * n01(rng), s * n01(rng)); };

  double sum_z2 = 0.0;
  int count = 0, outside = 0;
  for (int run = 0; run < kRuns; ++run) {
    ImuState x;
    x.R = so3::Exp(Vec3(0.3, -1.1, 0.7));
    x.p = Vec3(3, -2, 1);
    x.v = Vec3(0.5, 1.5, -0.2);
    Vec3 bg = Vec3(0.01, -0.02, 0.015) + normal3(1e-3), ba = Vec3(0.05, 0.1, -0.08) + normal3(1e-2);
    pipeline::ImuData imu;
    imu.source = "synthetic";
    pipeline::GroundTruth poses;
    poses.source = "synthetic poses";
    poses.full_state = false;
    std::vector<Vec3> true_bg, true_ba;
    for (std::size_t k = 0; k < motion.size(); ++k) {
      // The measurement: true rate + bias + white noise of variance density^2 / dt.
      ImuSample s = motion[k];
      s.gyro += bg + normal3(noise.gyro_noise_density / std::sqrt(dt));
      s.accel += ba + normal3(noise.accel_noise_density / std::sqrt(dt));
      imu.samples.push_back(s);
      ImuState measured = x;
      measured.R = x.R * so3::Exp(normal3(o.pose_sigma_rad));
      measured.p = x.p + normal3(o.pose_sigma_m);
      poses.t.push_back(motion[k].t);
      poses.x.push_back(measured);
      true_bg.push_back(bg);
      true_ba.push_back(ba);
      if (k + 1 == motion.size()) break;
      // The truth moves with the noise-free samples (zero bias) by the method's own scheme.
      SampleWindow w;
      ASSERT_TRUE(MakeWindow(motion.data(), motion.size(), motion[k].t, motion[k + 1].t, w).ok());
      const Preintegrated m = Preintegrate(reg, method, w, Vec3::Zero(), Vec3::Zero(), noise);
      x = Predict(x, m.delta, m.dt, g);
      // The bias random walk: variance density^2 * dt per step.
      bg += normal3(noise.gyro_random_walk * std::sqrt(dt));
      ba += normal3(noise.accel_random_walk * std::sqrt(dt));
    }
    const optimize::Result r = optimize::RunOptimize(reg, imu, poses, o);
    ASSERT_TRUE(r.converged && r.covariance_ok) << r.solver_message << r.covariance_message;
    const int og = 3 * static_cast<int>(std::find(r.labels.begin(), r.labels.end(), "bg") -
                                        r.labels.begin()),
              oa = 3 * static_cast<int>(std::find(r.labels.begin(), r.labels.end(), "ba") -
                                        r.labels.begin());
    // One keyframe per run (the middle one): keyframes of a run are correlated.
    const optimize::Keyframe& k = r.keyframes[r.keyframes.size() / 2];
    const auto sample = static_cast<std::size_t>(std::lround(k.t / dt));
    for (int a = 0; a < 3; ++a) {
      for (const auto& [err, var] :
           {std::pair<double, double>{k.x.bg[a] - true_bg[sample][a], k.cov(og + a, og + a)},
            {k.x.ba[a] - true_ba[sample][a], k.cov(oa + a, oa + a)}}) {
        const double z2 = err * err / var;
        sum_z2 += z2;
        outside += z2 > 9.0 ? 1 : 0;
        ++count;
      }
    }
  }
  // 600 squared standard normals (100 runs x 6 components; independent across runs, the six of
  // one run correlated, which only widens the spread): mean 1, standard deviation of the mean
  // sqrt(2 / 100) = 0.14 in the worst case of six fully correlated components. Five of those
  // either side: [0.3, 1.7]. A covariance half the true one (mean 2) or four times it (mean
  // 0.25) fails it. Measured: 1.09, with 2 of 600 beyond 3 sigma.
  const double mean_z2 = sum_z2 / count;
  EXPECT_GT(mean_z2, 0.3) << "the reported covariance is pessimistic";
  EXPECT_LT(mean_z2, 1.7) << "the reported covariance is optimistic";
  // Beyond 3 sigma: 0.27 % of a Gaussian, 1.6 expected in 600 independent values. In the worst
  // case of a run's six fully correlated, runs outside come six values at a time, 0.27 expected
  // of 100 (Poisson): more than three such runs (more than 18 values) has probability 2e-4.
  EXPECT_LE(outside, 18) << "of " << count << ", mean z^2 " << mean_z2;
  RecordProperty("mean_z2", std::to_string(mean_z2));
  RecordProperty("outside_3_sigma", outside);
}

}  // namespace
