#include "suite.h"

#include "bench_plugins.h"
#include "synthetic_motion.h"

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "imuconv/bridge.h"
#include "imuconv/kernels/preintegration.h"
#include "imuconv/kernels/rk4.h"
#include "imuconv/pipeline/output_file.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/result_arrays.h"
#include "imuconv/printable.h"
#include "imuconv/registry.h"
#include "imuconv/so3.h"
#include "montecarlo.h"

namespace imuconv::bench {
namespace {

Registry& Plugins() { return BenchPlugins("imuconv bench"); }

// 10 s at 200 Hz of smooth motion (sums of sinusoids, as the reference `smooth` kind).
const std::vector<ImuSample>& Samples() {
  static const std::vector<ImuSample> s = [] {
    std::vector<ImuSample> v;
    for (int k = 0; k <= 2000; ++k) {
      const double t = k / 200.0;
      v.push_back(SyntheticSample(t, 100.0 + t));
    }
    return v;
  }();
  return s;
}

SampleWindow Window() {
  SampleWindow w;
  const auto& s = Samples();
  // A window that could not be made would be timed empty, a benchmark of nothing: stop.
  if (const Status st = MakeWindow(s.data(), s.size(), s.front().t, s.back().t, w); !st.ok()) {
    std::fprintf(stderr, "imuconv bench: the benchmark window: %s\n", st.message().c_str());
    std::abort();
  }
  return w;
}

// The bias estimate every benchmark integrates with.
const Vec3 kBiasGyro(1e-3, -2e-3, 5e-4), kBiasAccel(0.02, -0.01, 0.03);

ImuNoise Noise() {
  // gyro and accelerometer noise densities, then gyro and accelerometer random walks
  return ImuNoise{1.7e-4, 2.0e-3, 1.9e-5, 3.0e-3};
}

PropagationInput Input() {
  PropagationInput in;
  in.x_s.R = so3::Exp(Vec3(0.1, -0.2, 0.3));
  in.x_s.bg = kBiasGyro;
  in.x_s.ba = kBiasAccel;
  in.cov_s = 1e-4 * Mat15::Identity();
  in.noise = Noise();
  in.window = Window();
  return in;
}

PreintegrationInput PreintInput() {
  return PreintegrationInputOf(Window(), kBiasGyro, kBiasAccel, Noise());
}

// A failing call ends the benchmark with its message (Google Benchmark reports
// error_occurred) instead of timing the error path.
bool Failed(benchmark::State& st, const Status& s) {
  if (s.ok()) return false;
  st.SkipWithError(s.message().c_str());
  return true;
}

void SetSamples(benchmark::State& st) {
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations()) *
                       static_cast<int64_t>(Samples().size() - 1));
}

/// Times call() (returning a Status, writing `out`) over the interval, per IMU sample.
template <class Out, class Call>
void TimeCalls(benchmark::State& st, Out& out, Call call) {
  for (auto _ : st) {
    if (Failed(st, call())) break;
    benchmark::DoNotOptimize(out);
  }
  SetSamples(st);
}

void BM_Preintegrate(benchmark::State& st, const char* id) {
  const auto pre = Plugins().preintegrator(id);
  const PreintegrationInput in = PreintInput();
  Preintegrated out;
  TimeCalls(st, out, [&] { return pre->integrate(in, out); });
}

// The native preintegration kernel with its compiled instance forced (the plugins pick the
// widest one the CPU runs, once per interval): what a CPU without AVX-512, or without AVX2,
// gets from the same code, and the portable path (what a compiler without vector extensions
// gets). Called directly, as the plugin calls it.
enum class Scheme { kManifold, kTangent };

void BM_PreintegrateInstance(benchmark::State& st, Scheme scheme, kernels::Isa isa) {
  const PreintegrationInput in = PreintInput();
  Preintegrated out;
  TimeCalls(st, out, [&] {
    return scheme == Scheme::kManifold ? kernels::IntegrateManifold<true>(in, out, nullptr, isa)
                                       : kernels::IntegrateTangent<true>(in, out, nullptr, isa);
  });
}

// rk4's compiled instances in imuconv_core (kernels/rk4.h), called directly with the instance
// forced, as its plugin calls the one kAuto picks: the portable (default-target) code, which
// kBaseline also runs, against the wider ones the CPU has.
void BM_Rk4Instance(benchmark::State& st, kernels::Isa isa) {
  const PropagationInput in = Input();
  PropagationResult out;
  TimeCalls(st, out, [&] { return kernels::PropagateRk4(in, out, 1, isa); });
}

void BM_Propagate(benchmark::State& st, const char* id) {
  const auto prop = Plugins().propagator(id);
  const PropagationInput in = Input();
  PropagationResult out;
  TimeCalls(st, out, [&] { return prop->propagate(in, out); });
}

void BM_PreintegrateByPropagation(benchmark::State& st, const char* id) {
  const SampleWindow w = Window();
  for (auto _ : st) {
    Preintegrated m = PreintegrateByPropagation(Plugins(), id, w, kBiasGyro, kBiasAccel, Noise());
    benchmark::DoNotOptimize(m);
  }
  SetSamples(st);
}

void BM_Conversion(benchmark::State& st, const char* from, const char* to) {
  ImuState x;
  x.R = so3::Exp(Vec3(0.4, -0.3, 1.2));
  x.p = Vec3(1, 2, 3);
  x.v = Vec3(-1, 0.5, 2);
  for (auto _ : st) {
    Mat15 J = Plugins().conversion(from, to, x);
    benchmark::DoNotOptimize(J);
  }
  st.SetItemsProcessed(st.iterations());
}

// The plugin path (registry lookup, virtual call into the shared object, convention
// handling) against the compile-time kernel called directly (the same code the plugin wraps,
// inlined here, no registry and no virtual call), interleaved in one loop so both see the
// same machine state. Reports the plugin path's time; `overhead_pct` is
// (plugin - direct) / direct.
using DirectKernel = Status (*)(const PropagationInput&, PropagationResult&);

Status DirectRk4(const PropagationInput& in, PropagationResult& out) {
  return kernels::PropagateRk4(in, out, 1);
}

void BM_PluginOverhead(benchmark::State& st, const char* id, DirectKernel direct_kernel) {
  const PropagationInput in = Input();
  PropagationResult out;
  double direct = 0.0, plugin = 0.0;
  for (auto _ : st) {
    const auto t0 = std::chrono::steady_clock::now();
    if (Failed(st, direct_kernel(in, out))) break;
    benchmark::DoNotOptimize(out);
    const auto t1 = std::chrono::steady_clock::now();
    out = Plugins().propagate(id, "left", in);
    benchmark::DoNotOptimize(out);
    const auto t2 = std::chrono::steady_clock::now();
    direct += std::chrono::duration<double>(t1 - t0).count();
    plugin += std::chrono::duration<double>(t2 - t1).count();
    st.SetIterationTime(std::chrono::duration<double>(t2 - t1).count());
  }
  st.counters["overhead_pct"] = 100.0 * (plugin - direct) / direct;
  SetSamples(st);
}

// ---- The whole job: `imuconv run examples/euroc_v1_01_full.json -o OUT` in-process ----
// Pipeline::Load, plugin loading (with the conventions' checks at load), reading the CSV
// files, the tasks, and the output written and committed as the CLI does (a temporary in the
// system's temporary directory, fsync'ed and renamed): JSON text, or the NPZ archive. Threads
// as the CLI's default (every core). Reported per IMU sample of the file (wall time, manual),
// with the RK4 kernel timed in the same iterations (BM_Propagate/rk4's call on its 2000-sample
// interval, interleaved so both see the same machine state): `kernel_ns_per_sample` and
// `x_kernel` = whole job / kernel, per sample. The data are found in the source tree
// (IMUCONV_SOURCE_DIR); without them the benchmark reports an error, never a figure.
std::string SourceFile(const std::string& rel) {
  return std::string(IMUCONV_SOURCE_DIR) + "/" + rel;
}

/// Data rows of an EuRoC CSV file (lines that are neither empty nor '#' comments); 0 if unreadable.
std::size_t DataRows(const std::string& path) {
  std::ifstream in(path);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#' && line != "\r") ++n;
  return n;
}

void BM_WholeJob(benchmark::State& st, const char* pipeline_file, const char* imu_file, bool npz) {
  const std::string path = SourceFile(pipeline_file);
  const std::size_t samples = DataRows(SourceFile(imu_file));
  if (samples == 0) {
    st.SkipWithError(
        ("cannot read the IMU data " + SourceFile(imu_file) + " (the source tree's examples/data)")
            .c_str());
    return;
  }
  const std::string out =
      (std::filesystem::temp_directory_path() /
       ("imuconv_bench_whole_job_" + std::to_string(::getpid()) + (npz ? ".npz" : ".json")))
          .string();
  const auto prop = Plugins().propagator("rk4");
  const PropagationInput in = Input();
  PropagationResult kernel_out;
  double job = 0.0, kernel = 0.0;
  for (auto _ : st) {
    const auto t0 = std::chrono::steady_clock::now();
    try {
      const pipeline::Pipeline p = pipeline::Pipeline::Load(path);
      pipeline::OutputFile file(out);
      pipeline::RunOptions ro;
      if (npz) {
        const pipeline::ResultArrays arrays = pipeline::RunToArrays(p, ro);
        pipeline::WriteResultNpz(arrays, [&](std::string_view s) { file.write(s); });
      } else {
        pipeline::RunToText(p, ro, [&](std::string_view s) { file.write(s); });
      }
      file.commit();
    } catch (const std::exception& e) {
      st.SkipWithError(e.what());
      break;
    }
    const auto t1 = std::chrono::steady_clock::now();
    if (Failed(st, prop->propagate(in, kernel_out))) break;
    benchmark::DoNotOptimize(kernel_out);
    const auto t2 = std::chrono::steady_clock::now();
    const double job_s = std::chrono::duration<double>(t1 - t0).count();
    job += job_s;
    kernel += std::chrono::duration<double>(t2 - t1).count();
    st.SetIterationTime(job_s);
  }
  std::error_code ec;
  std::filesystem::remove(out, ec);
  if (st.iterations() == 0 || kernel <= 0.0) return;
  const double job_ns =
      1e9 * job / (static_cast<double>(st.iterations()) * static_cast<double>(samples));
  const double kernel_ns =
      1e9 * kernel /
      (static_cast<double>(st.iterations()) * static_cast<double>(Samples().size() - 1));
  st.counters["kernel_ns_per_sample"] = kernel_ns;
  st.counters["x_kernel"] = job_ns / kernel_ns;
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations()) * static_cast<int64_t>(samples));
}

// ---- imuconv montecarlo's trials (apps/montecarlo/), in-process, one thread ----
// RunMonteCarlo on the 2000-step interval: the prediction once, then `kTrials` noisy trials,
// each drawing 12 normals per sample and integrating the mean (BM_MonteCarlo/rk4: the core's
// rk4 kernel, mean only) or the whole preintegration through the plugin
// (BM_MonteCarlo/rk4_full_path: the path before the mean-only one, and still the path of the
// methods that are not kernels of the core). Reported per sample per trial:
// ns = 1e9 / items_per_second (the one prediction is amortised over the trials, ~1 %).
// `imuconv montecarlo ... --trials 10000` on 2 cores costs about 10000 x 2000 x that / 2,
// plus the process start (bench/README.md, "montecarlo").
void BM_MonteCarlo(benchmark::State& st, const char* id, bool allow_mean_only) {
  constexpr int kTrials = 256;
  const PreintegrationMethod method =
      ResolvePreintegrationMethod(Plugins(), PluginKind::Propagator, id);
  montecarlo::Input in;
  in.samples = Samples();
  in.bg = kBiasGyro;
  in.ba = kBiasAccel;
  in.noise = Noise();
  montecarlo::Options o;
  o.trials = kTrials;
  o.seed = 1;
  o.threads = 1;
  o.allow_mean_only = allow_mean_only;
  for (auto _ : st) {
    try {
      const montecarlo::Result r =
          montecarlo::RunMonteCarlo(Plugins(), method, "preint_reference", in, o);
      if (allow_mean_only && r.trial_path != "mean_only") {
        st.SkipWithError(
            "the mean-only path was not taken (montecarlo.cpp: its nominal disagreed with the "
            "plugin's)");
        break;
      }
      benchmark::DoNotOptimize(r.stats.nees_mean);
    } catch (const std::exception& e) {
      st.SkipWithError(e.what());
      break;
    }
  }
  st.SetItemsProcessed(static_cast<int64_t>(st.iterations()) * kTrials *
                       static_cast<int64_t>(Samples().size() - 1));
}

}  // namespace

void RegisterAll() {
  for (const char* id : {"manifold", "tangent", "vins_fusion", "basalt"})
    benchmark::RegisterBenchmark((std::string("BM_Preintegrate/") + id).c_str(), BM_Preintegrate,
                                 id);
  for (const auto& [scheme, scheme_name] :
       {std::pair{Scheme::kManifold, "manifold"}, std::pair{Scheme::kTangent, "tangent"}})
    for (const kernels::Isa isa : {kernels::Isa::kPortable, kernels::Isa::kBaseline,
                                   kernels::Isa::kAvx2, kernels::Isa::kAvx512})
      if (kernels::IsaAvailable(isa))
        benchmark::RegisterBenchmark(
            (std::string("BM_PreintegrateInstance/") + scheme_name + "/" + kernels::IsaName(isa))
                .c_str(),
            BM_PreintegrateInstance, scheme, isa);
  for (const kernels::Isa isa :
       {kernels::Isa::kPortable, kernels::Isa::kAvx2, kernels::Isa::kAvx512})
    if (kernels::IsaAvailable(isa))
      benchmark::RegisterBenchmark((std::string("BM_Rk4Instance/") + kernels::IsaName(isa)).c_str(),
                                   BM_Rk4Instance, isa);
  for (const char* id : {"euler", "midpoint", "rk4", "openvins_discrete", "openvins_rk4",
                         "openvins_analytical", "fast_lio2_as_configured"})
    benchmark::RegisterBenchmark((std::string("BM_Propagate/") + id).c_str(), BM_Propagate, id);
  benchmark::RegisterBenchmark("BM_PreintegrateByPropagation/rk4", BM_PreintegrateByPropagation,
                               "rk4");
  benchmark::RegisterBenchmark("BM_Conversion/left/gtsam_navstate", BM_Conversion, "left",
                               "gtsam_navstate");
  benchmark::RegisterBenchmark("BM_PluginOverhead/rk4", BM_PluginOverhead, "rk4", &DirectRk4)
      ->UseManualTime();
  for (const bool npz : {false, true})
    benchmark::RegisterBenchmark(npz ? "BM_WholeJob/euroc_full_npz" : "BM_WholeJob/euroc_full_json",
                                 BM_WholeJob, "examples/euroc_v1_01_full.json",
                                 "examples/data/V1_01_easy_imu0.csv", npz)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_MonteCarlo/rk4", BM_MonteCarlo, "rk4", true)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_MonteCarlo/rk4_full_path", BM_MonteCarlo, "rk4", false)
      ->Unit(benchmark::kMillisecond);
}

int Main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RegisterAll();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace imuconv::bench
