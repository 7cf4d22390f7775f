// What the tests of imuconv::ceres share: a simulated IMU run over a few keyframes with known
// biases, and a small problem (preintegration factors, pose measurements, a prior) built from it
// in any state convention.
#pragma once

#include <ceres/ceres.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "imuconv/bridge.h"
#include "imuconv/ceres/pose_factors.h"
#include "imuconv/ceres/preintegration_factor.h"
#include "imuconv/ceres/state_block.h"
#include "imuconv/ceres/state_manifold.h"
#include "imuconv/so3.h"

namespace imuconv::ceres_test {

using namespace imuconv::ceres_factors;

/// Densities of a consumer-grade IMU, large enough that a one-second run says something of
/// its biases.
inline ImuNoise SimulatedNoise() {
  ImuNoise n;
  n.gyro_noise_density = 2e-3;   // rad/s/sqrt(Hz)
  n.accel_noise_density = 2e-2;  // m/s^2/sqrt(Hz)
  n.gyro_random_walk = 2e-4;     // rad/s^2/sqrt(Hz)
  n.accel_random_walk = 2e-3;    // m/s^3/sqrt(Hz)
  return n;
}

/// A run: samples at `rate_hz` from t = 0, keyframes every `keyframe_step` s, and the true
/// state (biases included) at each keyframe.
struct SimulatedRun {
  std::vector<ImuSample> samples;
  std::vector<double> keyframe_t;
  std::vector<ImuState> truth;
};

/// The body's true angular rate and specific force (bias-free) at time t: smooth, every axis
/// excited, so that both biases are observable from pose measurements.
inline void TrueMotion(double t, Vec3& omega, Vec3& force) {
  omega = Vec3(0.6 * std::sin(2.0 * t), 0.4 * std::cos(3.0 * t), 0.5 * std::sin(t) + 0.2);
  force = Vec3(1.0 * std::sin(1.5 * t), 0.8 * std::cos(2.0 * t), 9.81 + 0.5 * std::sin(2.5 * t));
}

/// The truth is the forward-Euler (zero-order hold) recursion of the true motion, the scheme of
/// the `manifold` preintegrator (GTSAM's ManifoldPreintegration), so its prediction from the
/// noise-free samples is exact and every difference a test sees is the simulated noise. The
/// measured sample k is the true motion plus the bias b_k plus white noise of variance
/// sigma^2 / h (the forward cell [t_k, t_k+1], noise_simulation.h); the biases walk by
/// N(0, sigma_w^2 h) per step, as the continuous model the covariance integrates (section 2.1).
/// `noisy` false: no white noise and no walk (the biases stay b0).
inline SimulatedRun Simulate(int keyframes, double keyframe_step, double rate_hz,
                             const ImuNoise& noise, const Vec3& bg0, const Vec3& ba0, bool noisy,
                             std::mt19937& rng, const Vec3& gravity) {
  const int per_keyframe = static_cast<int>(std::lround(keyframe_step * rate_hz));
  const double h = 1.0 / rate_hz;
  const int n = (keyframes - 1) * per_keyframe + 1;
  std::normal_distribution<double> unit(0.0, 1.0);
  const auto draw = [&](double sigma) {
    return noisy ? Vec3(sigma * unit(rng), sigma * unit(rng), sigma * unit(rng)) : Vec3::Zero();
  };
  SimulatedRun run;
  ImuState x;
  x.R = so3::Exp(Vec3(0.1, -0.2, 0.3));
  x.v = Vec3(0.5, -0.2, 0.1);
  x.bg = bg0;
  x.ba = ba0;
  for (int k = 0; k < n; ++k) {
    const double t = k * h;
    if (k % per_keyframe == 0) {
      run.keyframe_t.push_back(t);
      run.truth.push_back(x);
    }
    Vec3 omega, force;
    TrueMotion(t, omega, force);
    ImuSample s;
    s.t = t;
    s.gyro = omega + x.bg + draw(noise.gyro_noise_density / std::sqrt(h));
    s.accel = force + x.ba + draw(noise.accel_noise_density / std::sqrt(h));
    run.samples.push_back(s);
    // Forward Euler in the world frame (the increment's recursion composed with Predict).
    const Vec3 a_world = x.R * force;
    x.p += x.v * h + 0.5 * h * h * (gravity + a_world);
    x.v += h * (gravity + a_world);
    x.R = x.R * so3::Exp(omega * h);
    x.bg += draw(noise.gyro_random_walk * std::sqrt(h));
    x.ba += draw(noise.accel_random_walk * std::sqrt(h));
  }
  return run;
}

/// Gravity in the world frame of the simulated runs (z up), m/s^2.
inline const Vec3 kSimulatedGravity(0.0, 0.0, -9.81);

/// Simulate() with the start biases most tests use (a consumer IMU's order: 0.01 to 0.02 rad/s,
/// 0.05 to 0.2 m/s^2) and kSimulatedGravity.
inline SimulatedRun SimulateAtTypicalBiases(int keyframes, double keyframe_step, double rate_hz,
                                            bool noisy, std::mt19937& rng) {
  return Simulate(keyframes, keyframe_step, rate_hz, SimulatedNoise(), Vec3(0.01, -0.02, 0.015),
                  Vec3(0.1, -0.05, 0.2), noisy, rng, kSimulatedGravity);
}

/// A simulated run and the preintegration method of the factors a test builds on it.
struct RunWithMethod {
  SimulatedRun run;
  PreintegrationMethod method;
};

/// Two keyframes 0.2 s apart at 200 Hz, without noise, bias walk or bias, and the `manifold`
/// preintegrator: the plain run on which the hostile-input tests vary one thing at a time.
inline RunWithMethod NoiseFreeZeroBiasRun(const Registry& reg) {
  std::mt19937 rng(3);
  RunWithMethod d;
  d.run = Simulate(2, 0.2, 200.0, SimulatedNoise(), Vec3::Zero(), Vec3::Zero(), false, rng,
                   kSimulatedGravity);
  d.method = ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, "manifold");
  return d;
}

/// Pose measurement noise of the simulated runs.
inline constexpr double kSigmaPos = 0.005;  // m
inline constexpr double kSigmaRot = 0.002;  // rad

/// The prior on the first keyframe, in the reference chart `left` ([p, theta, v, bg, ba]).
inline Mat15 PriorCovarianceLeft() {
  Vec15 sd;
  sd << Vec3::Constant(0.01), Vec3::Constant(0.01), Vec3::Constant(0.05), Vec3::Constant(0.01),
      Vec3::Constant(0.05);
  return sd.cwiseAbs2().asDiagonal();
}

/// One problem: a factor per keyframe pair, a pose measurement per keyframe, a prior on the
/// first; each keyframe's block parameterized by a StateManifold of `convention`. The members
/// own what the problem refers to (factors, manifolds) and outlive it (declared first).
struct SmallProblem {
  std::vector<std::unique_ptr<PreintegrationFactor>> factors;
  std::vector<std::array<double, kStateBlockSize>> blocks;
  std::unique_ptr<::ceres::Problem> problem;
};

/// Measurements, drawn once per run so that every convention sees the same numbers.
struct Measurements {
  std::vector<Mat3> R;
  std::vector<Vec3> p;
  ImuState prior;  ///< the prior's mean
};

inline Measurements DrawMeasurements(const SimulatedRun& run, bool noisy, std::mt19937& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const auto draw = [&](double sigma) {
    return noisy ? Vec3(sigma * unit(rng), sigma * unit(rng), sigma * unit(rng)) : Vec3::Zero();
  };
  Measurements m;
  for (const ImuState& x : run.truth) {
    m.R.push_back(so3::Exp(draw(kSigmaRot)) * x.R);  // r = Log(R_meas^T R) ~ N(0, sigma^2)
    m.p.push_back(x.p + draw(kSigmaPos));
  }
  // The prior's mean drawn from N(truth, P) in the left chart, so that the prior is a
  // measurement like the others (the Monte Carlo's estimates then scatter as the covariance).
  const Mat15 L = PriorCovarianceLeft().llt().matrixL();
  Vec15 z;
  for (int i = 0; i < 15; ++i) z[i] = noisy ? unit(rng) : 0.0;
  LeftRetract(run.truth.front(), L * z, m.prior);
  return m;
}

/// The initial values the solver starts from: the truth moved by a fixed, deterministic offset,
/// so that the solver has work to do.
inline ImuState Perturbed(const ImuState& x, int k) {
  ImuState y = x;
  y.R = so3::Exp(Vec3(0.01, -0.02, 0.015) * (1 + k % 3)) * x.R;
  y.p += Vec3(0.05, -0.03, 0.02);
  y.v += Vec3(-0.02, 0.04, 0.01);
  y.bg += Vec3(0.002, -0.001, 0.003);
  y.ba += Vec3(-0.02, 0.01, 0.03);
  return y;
}

/// What every small problem holds besides its IMU factors: a block per keyframe in `blocks`,
/// started at Perturbed(truth) and parameterized by a StateManifold of `convention`, the
/// keyframe's pose measurement, and the prior on the first keyframe. The problem owns the
/// manifolds; `blocks` must outlive it.
inline std::unique_ptr<::ceres::Problem> NewProblemOfPosesAndPrior(
    const Registry& reg, const std::string& convention, const SimulatedRun& run,
    const Measurements& meas, std::vector<std::array<double, kStateBlockSize>>& blocks) {
  ::ceres::Problem::Options po;
  po.manifold_ownership = ::ceres::TAKE_OWNERSHIP;
  auto problem = std::make_unique<::ceres::Problem>(po);
  const std::size_t K = run.truth.size();
  blocks.resize(K);
  for (std::size_t k = 0; k < K; ++k) {
    ToStateBlock(Perturbed(run.truth[k], static_cast<int>(k)), blocks[k].data());
    problem->AddParameterBlock(blocks[k].data(), kStateBlockSize,
                               new StateManifold(reg, convention));
    problem->AddResidualBlock(MakePoseMeasurement(meas.R[k], meas.p[k], kSigmaPos, kSigmaRot),
                              nullptr, blocks[k].data());
  }
  // The prior in the chart it was drawn in (left), whatever the manifold's convention.
  problem->AddResidualBlock(MakeStatePrior(reg, "left", meas.prior, PriorCovarianceLeft()), nullptr,
                            blocks[0].data());
  return problem;
}

/// The states a problem's blocks hold (after a solve: its optimum).
inline std::vector<ImuState> StatesOfBlocks(
    const std::vector<std::array<double, kStateBlockSize>>& blocks) {
  std::vector<ImuState> states;
  for (const auto& b : blocks) states.push_back(FromStateBlock(b.data()));
  return states;
}

/// What the chart-independence tests solve in every state convention: a noisy run of six
/// keyframes 0.2 s apart at the typical biases, its measurements drawn after it from the same
/// generator (seed 20261127), and the `manifold` preintegrator for its factors.
struct ChartIndependenceData {
  SimulatedRun run;
  Measurements meas;
  PreintegrationMethod method;
};

inline ChartIndependenceData MakeChartIndependenceData(const Registry& reg) {
  std::mt19937 rng(20261127);
  ChartIndependenceData d;
  d.run = SimulateAtTypicalBiases(6, 0.2, 200.0, true, rng);
  d.meas = DrawMeasurements(d.run, true, rng);
  d.method = ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, "manifold");
  return d;
}

/// The factors are linearized at the prior's biases (what an estimator knows before the solve)
/// unless `linearize_at` gives others ({bg, ba}).
inline void BuildProblem(const Registry& reg, const std::string& convention,
                         const PreintegrationMethod& method, const PreintegrationFactorOptions& fo,
                         const SimulatedRun& run, const Measurements& meas, SmallProblem& out,
                         const std::pair<Vec3, Vec3>* linearize_at = nullptr) {
  out.problem = NewProblemOfPosesAndPrior(reg, convention, run, meas, out.blocks);
  for (std::size_t k = 0; k + 1 < run.truth.size(); ++k) {
    out.factors.push_back(std::make_unique<PreintegrationFactor>(
        reg, method, run.samples, run.keyframe_t[k], run.keyframe_t[k + 1], SimulatedNoise(),
        linearize_at ? linearize_at->first : meas.prior.bg,
        linearize_at ? linearize_at->second : meas.prior.ba, fo));
    out.problem->AddResidualBlock(out.factors.back()->MakeCostFunction(), nullptr,
                                  out.blocks[k].data(), out.blocks[k + 1].data());
  }
}

/// Tight tolerances: the tests compare optima to 1e-8, so the solver stops well below that.
inline ::ceres::Solver::Options TightSolverOptions() {
  ::ceres::Solver::Options o;
  o.linear_solver_type = ::ceres::DENSE_QR;
  o.max_num_iterations = 100;
  o.function_tolerance = 1e-16;
  o.gradient_tolerance = 1e-14;
  o.parameter_tolerance = 1e-14;
  o.num_threads = 1;
  o.logging_type = ::ceres::SILENT;
  return o;
}

}  // namespace imuconv::ceres_test
