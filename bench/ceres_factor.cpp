// imuconv-bench-ceres: one preintegration factor's evaluation (residual and the two 15x16
// ambient Jacobians Ceres asks for) per keyframe pair, and its re-integration, for a native
// preintegrator and for preintegration by propagation; the same evaluation of each residual
// plugin's own cost (NativeResidualFactor: n x 16 Jacobians); and imuconv optimize's whole solve on
// EuRoC V1_01 (examples/data, the source tree's: IMUCONV_SOURCE_DIR), with and without the
// marginal covariances. Built only with imuconv::ceres; a program
// of its own so that `imuconv bench`'s set stays the same with and without Ceres.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_plugins.h"
#include "imuconv/bridge.h"
#include "imuconv/ceres/native_residual_factor.h"
#include "imuconv/ceres/preintegration_factor.h"
#include "imuconv/ceres/state_block.h"
#include "imuconv/optimize/optimize.h"
#include "imuconv/optimize/optimize_input.h"
#include "imuconv/printable.h"
#include "imuconv/so3.h"
#include "synthetic_motion.h"

namespace imuconv::bench_ceres {
namespace {

using namespace imuconv::ceres_factors;

const Registry& Plugins() { return bench::BenchPlugins("imuconv-bench-ceres"); }

// One keyframe pair 0.1 s apart at 200 Hz (imuconv optimize's default --keyframe-step on EuRoC),
// the smooth motion of synthetic_motion.h, as bench/suite.cpp integrates it.
std::vector<ImuSample> KeyframeSamples() {
  std::vector<ImuSample> v;
  for (int k = 0; k <= 20; ++k) {
    const double t = k / 200.0;
    v.push_back(bench::SyntheticSample(t, t));
  }
  return v;
}

const ImuNoise kNoise{1.7e-4, 2.0e-3, 1.9e-5, 3.0e-3};
const Vec3 kBiasGyro(1e-3, -2e-3, 5e-4), kBiasAccel(0.02, -0.01, 0.03);

std::unique_ptr<PreintegrationFactor> MakeFactor(PluginKind kind, const char* id,
                                                 ResidualKind residual) {
  PreintegrationFactorOptions fo;
  fo.kind = residual;
  return std::make_unique<PreintegrationFactor>(
      Plugins(), ResolvePreintegrationMethod(Plugins(), kind, id), KeyframeSamples(), 0.0, 0.1,
      kNoise, kBiasGyro, kBiasAccel, fo);
}

/// The two state blocks every evaluation here is timed at: a start state and the end state
/// predicted from it by the keyframe pair's increment `delta` (0.1 s), the start biases moved
/// off the linearization point so that the first-order correction is computed.
struct StateBlocks {
  std::array<double, kStateBlockSize> start, end;
};

StateBlocks StatesNearPrediction(const PreintIncrement& delta) {
  ImuState xs;
  xs.R = so3::Exp(Vec3(0.1, -0.2, 0.3));
  xs.v = Vec3(0.5, -0.2, 0.1);
  xs.bg = kBiasGyro + Vec3(1e-4, 0, 0);
  xs.ba = kBiasAccel + Vec3(0, 1e-3, 0);
  const ImuState xe = Predict(xs, delta, 0.1, Vec3(0, 0, -9.81));
  StateBlocks b;
  ToStateBlock(xs, b.start.data());
  ToStateBlock(xe, b.end.data());
  return b;
}

void BM_CeresFactorEvaluate(benchmark::State& st, PluginKind kind, const char* id,
                            ResidualKind residual, bool jacobians) {
  std::unique_ptr<PreintegrationFactor> factor;
  try {
    factor = MakeFactor(kind, id, residual);
  } catch (const std::exception& e) {
    st.SkipWithError(e.what());
    return;
  }
  std::unique_ptr<::ceres::CostFunction> cost(factor->MakeCostFunction());
  const StateBlocks states = StatesNearPrediction(factor->measurement().delta);
  const double* blocks[] = {states.start.data(), states.end.data()};
  std::array<double, 15> r;
  std::array<double, 15 * kStateBlockSize> j0, j1;
  double* jac[] = {j0.data(), j1.data()};
  for (auto _ : st) {
    const bool ok = cost->Evaluate(blocks, r.data(), jacobians ? jac : nullptr);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(r.data());
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(st.iterations());  // keyframe pairs
}

void BM_CeresFactorReintegrate(benchmark::State& st, PluginKind kind, const char* id) {
  std::unique_ptr<PreintegrationFactor> factor;
  try {
    factor = MakeFactor(kind, id, ResidualKind::Gtsam);
  } catch (const std::exception& e) {
    st.SkipWithError(e.what());
    return;
  }
  int k = 0;
  for (auto _ : st) {
    factor->Reintegrate(kBiasGyro + Vec3(1e-5 * (k & 1), 0, 0), kBiasAccel);
    ++k;
    benchmark::DoNotOptimize(factor->measurement().delta.dp.data());
  }
  st.SetItemsProcessed(st.iterations());
}

/// A residual plugin's own cost (NativeResidualFactor) on the `manifold` measurement of the same
/// keyframe pair, at the same two states as BM_CeresFactorEvaluate: the residual and both n x 16
/// ambient Jacobians.
void BM_NativeResidualEvaluate(benchmark::State& st, const std::string& id) {
  std::unique_ptr<NativeResidualFactor> factor;
  try {
    factor = std::make_unique<NativeResidualFactor>(
        Plugins(), id,
        ResolvePreintegrationMethod(Plugins(), PluginKind::Preintegrator, "manifold"),
        KeyframeSamples(), 0.0, 0.1, kNoise, kBiasGyro, kBiasAccel);
  } catch (const std::exception& e) {
    st.SkipWithError(e.what());
    return;
  }
  std::unique_ptr<::ceres::CostFunction> cost(factor->MakeCostFunction());
  const StateBlocks states = StatesNearPrediction(factor->preintegration().measurement().delta);
  const double* blocks[] = {states.start.data(), states.end.data()};
  const int n = cost->num_residuals();
  std::vector<double> r(n), j0(n * kStateBlockSize), j1(n * kStateBlockSize);
  double* jac[] = {j0.data(), j1.data()};
  for (auto _ : st) {
    const bool ok = cost->Evaluate(blocks, r.data(), jac);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(r.data());
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(st.iterations());  // keyframe pairs
}

/// The whole of examples/data's V1_01 (1448 keyframes at 0.1 s, the vicon2gt poses as pose
/// measurements), solved as `imuconv optimize --keyframe-step 0.1` does with the EuRoC
/// datasheet's densities (examples/euroc_v1_01_full.json): reading the files is outside the
/// timing, the re-integration rounds and (with `covariance`) the marginals inside it.
void BM_OptimizeEurocV101(benchmark::State& st, bool covariance) {
  const std::string dir = std::string(IMUCONV_SOURCE_DIR) + "/examples/data/";
  optimize::Input in;
  try {
    in = optimize::ReadFileInput(dir + "V1_01_easy_imu0.csv",
                                 dir + "V1_01_easy_groundtruth_vicon2gt.csv");
  } catch (const std::exception& e) {
    st.SkipWithError(e.what());
    return;
  }
  optimize::Options o;
  o.keyframe_step = 0.1;
  o.noise = ImuNoise{1.6968e-4, 2.0e-3, 1.9393e-5, 3.0e-3};
  o.covariance = covariance;
  std::size_t keyframes = 0;
  for (auto _ : st) {
    const optimize::Result r = optimize::RunOptimize(Plugins(), in.imu, in.poses, o);
    if (!r.converged) st.SkipWithError("the solve did not converge");
    keyframes = r.keyframes.size();
  }
  st.counters["keyframes"] = static_cast<double>(keyframes);
}

}  // namespace
}  // namespace imuconv::bench_ceres

int main(int argc, char** argv) {
  using namespace imuconv;
  using namespace imuconv::bench_ceres;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  const struct {
    PluginKind kind;
    const char* id;
  } methods[] = {{PluginKind::Preintegrator, "manifold"}, {PluginKind::Propagator, "rk4"}};
  for (const auto& m : methods) {
    for (const auto& [residual, name] :
         {std::pair{ResidualKind::Gtsam, "gtsam"}, std::pair{ResidualKind::Forster, "forster"}})
      benchmark::RegisterBenchmark(
          (std::string("BM_CeresFactorEvaluate/") + m.id + "/" + name).c_str(),
          BM_CeresFactorEvaluate, m.kind, m.id, residual, true);
    benchmark::RegisterBenchmark(
        (std::string("BM_CeresFactorEvaluate/") + m.id + "/gtsam/residual_only").c_str(),
        BM_CeresFactorEvaluate, m.kind, m.id, ResidualKind::Gtsam, false);
    benchmark::RegisterBenchmark((std::string("BM_CeresFactorReintegrate/") + m.id).c_str(),
                                 BM_CeresFactorReintegrate, m.kind, m.id);
  }
  for (const std::string& id : Plugins().ids(PluginKind::Residual))
    benchmark::RegisterBenchmark(("BM_NativeResidualEvaluate/manifold/" + id).c_str(),
                                 BM_NativeResidualEvaluate, id);
  for (const bool covariance : {false, true})
    benchmark::RegisterBenchmark(
        covariance ? "BM_OptimizeEurocV101/with_covariances" : "BM_OptimizeEurocV101/solve_only",
        BM_OptimizeEurocV101, covariance)
        ->Unit(benchmark::kSecond)
        ->Iterations(1)
        ->UseRealTime();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
