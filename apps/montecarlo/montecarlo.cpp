// The simulation of imuconv montecarlo (docs/montecarlo.md). Truth model, for the continuous
// noise model (the paper, section 2.1; tests/integrators/monte_carlo.cpp and
// tests/preintegrators/monte_carlo.cpp draw it the same way):
//   the case's samples z_k are the measurements; the truth is z_k - n_k - beta_k with white
//   noise n_k ~ N(0, sigma^2/dt_k I) and the accumulated bias walk beta_k (beta_0 = 0,
//   beta_{k+1} = beta_k + N(0, sigma_b^2 dt I) over the step k -> k+1). Integrating the truth
//   with the same bias estimate gives the true increment, whose bias entry is beta_K (the
//   bias grew by it over the interval). The end error is conv.local(nominal, truth): the
//   predicted covariance is that of the truth about the estimate.
// dt_k is the length of sample k's cell: the part of the interval the method's integral
// weights sample k over, so that the weighted sum of the sample noises is the integral of one
// continuous white noise over the interval (the note, section 2.1's sigma^2/dt discretisation,
// with the cells partitioning [t_s, t_e]):
//   forward (euler, manifold, tangent, ...: sample k held over [t_k, t_k+1]): dt_k = h_k;
//   backward (Basalt's feeding, held over the step that ends at it): dt_k = h_k-1;
//   centered (methods that average the two ends of a step or interpolate linearly between
//   knots: midpoint, rk4, vins_fusion, the openvins_* propagators): sample k weighs
//   (h_k-1 + h_k) / 2 in the rotation increment (trapezoid weights), over the cell
//   [t_k - h_k-1/2, t_k + h_k/2], half cells at the two ends: dt_k = (h_k-1 + h_k) / 2.
// Held over a forward cell instead, a centered method's theta error has the variance
// sigma^2 sum_k ((h_k-1 + h_k)/2)^2 / h_k, which exceeds sigma^2 T on unequal steps (by 3.0 %
// on jitter-0, 2.8 % on jitter-1; equal steps: only the two end samples differ, 1/(2K)):
// that was the rk4 "inconsistency" on the jittered cases, a simulation that did not draw the
// continuous noise these methods' covariances (rightly) integrate.
// Which cells a method has, and how it reads the noise, the method's plugin says
// (noise_simulation(), core/include/imuconv/noise_simulation.h); this file names no method.
#include "montecarlo.h"

#include "normal.h"
#include "trial_nees.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <system_error>
#include <thread>

#include "imuconv/increment_mean.h"
#include "imuconv/noise_simulation.h"
#include "imuconv/printable.h"
#include "imuconv/status.h"
#include "imuconv/window.h"

namespace imuconv::montecarlo {
namespace {

/// The resolved method's plugin's simulation facts (noise_simulation.h).
NoiseSimulation NoiseSimulationOf(const PreintegrationMethod& method) {
  if (method.kind == PluginKind::Preintegrator && method.preintegrator)
    return method.preintegrator->noise_simulation();
  if (method.kind == PluginKind::Propagator && method.propagator)
    return method.propagator->noise_simulation();
  return NoiseSimulation();
}

const char* CellNote(SampleCells cells) {
  switch (cells) {
    case SampleCells::kBackward:
      return "; each sample's white noise is over the step ending at it (sigma^2/h_k-1)";
    case SampleCells::kCentered:
      return "; each sample's white noise is over its centered cell, half of each step beside it "
             "(sigma^2/((h_k-1 + h_k)/2)), as the method averages the two ends of a step";
    case SampleCells::kForward:
    default:  // an unknown value: simulated forward (NoiseModelFor says so)
      break;
  }
  return "; each sample's white noise is over the step it starts (sigma^2/h_k)";
}

/// Preintegrates over all of `samples` with the method (the case's noise, for the prediction).
Preintegrated PreintegrateAll(const Registry& reg, const PreintegrationMethod& method,
                              const std::vector<ImuSample>& s, const Input& in) {
  SampleWindow window;
  const Status st = MakeWindow(s.data(), s.size(), s.front().t, s.back().t, window);
  if (!st.ok()) throw Error("montecarlo: cannot window the samples: " + st.message());
  return Preintegrate(reg, method, window, in.bg, in.ba, in.noise);
}

/// The mean alone of the method's trials, by its plugin's optional increment_mean()
/// (increment_mean.h): "not provided" by a plugin without it.
Status IncrementMean(const PreintegrationMethod& method, const SampleWindow& window,
                     const Input& input, PreintIncrement& delta) {
  const PreintegrationInput in = PreintegrationInputOf(window, input.bg, input.ba, input.noise);
  if (method.kind == PluginKind::Preintegrator && method.preintegrator)
    return method.preintegrator->increment_mean(in, delta);
  if (method.kind == PluginKind::Propagator && method.propagator)
    return method.propagator->increment_mean(in, delta);
  return IncrementMeanNotProvided();
}

/// The largest offset, in standard deviations of the prediction (whitened), accepted between
/// the mean-only path's nominal increment and the full path's. Every trial's error then
/// carries an offset below 1e-6 sigma: it moves a trial's NEES (about 15) by about
/// 2 sqrt(15) 1e-6 ~ 1e-5, far inside the NEES bounds even at 10^7 trials (15 -+ 0.003), and
/// the sample covariance by 1e-12 relative. Rounding differences are ~1e-10 sigma and below.
constexpr double kMeanOffsetSigmas = 1e-6;

bool SameBits(const PreintIncrement& a, const PreintIncrement& b) {
  return std::memcmp(a.dR.data(), b.dR.data(), sizeof(double) * 9) == 0 &&
         std::memcmp(a.dp.data(), b.dp.data(), sizeof(double) * 3) == 0 &&
         std::memcmp(a.dv.data(), b.dv.data(), sizeof(double) * 3) == 0;
}

}  // namespace

NoiseModel NoiseModelFor(const PreintegrationMethod& method) {
  const NoiseSimulation sim = NoiseSimulationOf(method);
  NoiseModel m;
  // The names of `simulated` are the output's since its first release ("basalt" was the first
  // scheme to read the noise so); the plugin's note says which scheme and why.
  switch (sim.reading) {
    case NoiseReading::kWalkInIncrementOnly:
      m.simulated = "basalt";
      m.note =
          "white noise sigma^2/dt per sample; bias random walk in the increment's bias entries "
          "only, the samples integrated at the constant bias estimate";
      break;
    case NoiseReading::kPerSampleStd:
      m.simulated = "basalt_per_sample";
      m.note =
          "white noise with the two white-noise numbers as per-sample standard deviations (not "
          "divided by sqrt dt)";
      break;
    case NoiseReading::kContinuous:
    default:
      m.simulated = "continuous";
      m.note =
          "white noise sigma^2/dt per sample and a bias random walk sigma_b^2 dt per step, folded "
          "into the samples";
      break;
  }
  if (sim.note) m.note += Printable(sim.note);
  m.matches = sim.simulable;
  // A value outside the enums (a plugin built against another header) is simulated as the
  // defaults (the switches' `default`), and said, never taken silently.
  const int cells = static_cast<int>(sim.cells), reading = static_cast<int>(sim.reading);
  if (cells < 0 || cells > static_cast<int>(SampleCells::kCentered) || reading < 0 ||
      reading > static_cast<int>(NoiseReading::kPerSampleStd)) {
    m.matches = false;
    m.note += "; MISMATCH: the plugin's noise_simulation() gave cells " + std::to_string(cells) +
              " and reading " + std::to_string(reading) +
              ", not all known here; simulated with forward cells and continuous densities";
  }
  return m;
}

std::string DefaultConvention(const PreintegrationMethod& method) {
  if (method.kind == PluginKind::Preintegrator && method.cov_convention)
    return method.cov_convention->id();
  return "preint_reference";
}

Result RunMonteCarlo(const Registry& reg, const PreintegrationMethod& method,
                     const std::string& convention, const Input& input, const Options& options) {
  std::vector<Vec15> errors;
  Result res = RunTrials(reg, method, convention, input, options, 0, options.trials, errors);
  Conclude(res, errors);
  return res;
}

Result RunTrials(const Registry& reg, const PreintegrationMethod& method,
                 const std::string& convention, const Input& input, const Options& options,
                 int first, int end, std::vector<Vec15>& errors) {
  if (first < 0 || first > end || end > options.trials)
    throw Error("montecarlo: trials [" + std::to_string(first) + ", " + std::to_string(end) +
                ") are not within the " + std::to_string(options.trials) + " trials of the run");
  const auto conv = reg.increment_convention(convention);
  const std::vector<ImuSample>& z = input.samples;
  const std::size_t K = z.size() - 1;

  Result res;
  res.method = method.id;
  res.method_kind = method.kind == PluginKind::Propagator ? "propagator" : "preintegrator";
  res.convention = conv->id();
  res.trials = options.trials;
  res.seed = options.seed;
  res.noise_scale = options.noise_scale;
  res.duration = z.back().t - z.front().t;
  res.samples = z.size();
  res.noise_model = NoiseModelFor(method);
  if (options.noise_scale != 1.0) {
    res.noise_model.matches = false;
    res.noise_model.note += "; the simulated densities are scaled by " +
                            std::to_string(options.noise_scale) +
                            " against the prediction's (--noise-scale), deliberately";
  }
  const bool walk_in_samples = res.noise_model.simulated == "continuous";
  const bool per_sample_std = res.noise_model.simulated == "basalt_per_sample";
  const SampleCells cells = NoiseSimulationOf(method).cells;
  if (!per_sample_std) res.noise_model.note += CellNote(cells);

  // The prediction and the nominal increment: the full path, once.
  const Preintegrated nominal = PreintegrateAll(reg, method, z, input);
  res.predicted = Express(reg, nominal, res.convention).cov;

  // The trials need only the mean. Where the method's plugin gives its mean alone
  // (increment_mean(), increment_mean.h; the core's kernels give it through their plugins,
  // kernels/mean_only.h), the trials call it, provided it reproduces the full path's nominal
  // increment: bit for bit where the two are the same compiled arithmetic, or to within
  // kMeanOffsetSigmas of the prediction's standard deviations where a separate compilation
  // only sums in another order (rounding, ~1e-15 relative). A plugin's mean-only integration
  // is not taken on trust: this check is what keeps a wrong one (a user's plugin, an override)
  // from giving a wrong verdict in silence; refused, each trial runs the full path, and the
  // result says why (mean_only_refused).
  bool mean_only = false;
  if (options.allow_mean_only) {
    SampleWindow window;
    PreintIncrement mean;
    Status st = MakeWindow(z.data(), z.size(), z.front().t, z.back().t, window);
    if (st.ok()) st = IncrementMean(method, window, input, mean);
    if (!st.ok()) {
      if (!IsIncrementMeanNotProvided(st))
        res.mean_only_refused = "the plugin's increment_mean() failed on the nominal samples: " +
                                Printable(st.message());
    } else if (SameBits(mean, nominal.delta)) {
      mean_only = true;
    } else {
      mean.dbg = nominal.delta.dbg;
      mean.dba = nominal.delta.dba;
      Vec15 offset;
      conv->local(nominal.delta, mean, offset);
      const Eigen::LLT<Mat15> llt(res.predicted);
      res.mean_only_offset = llt.info() == Eigen::Success
                                 ? Vec15(llt.matrixL().solve(offset)).norm()
                                 : std::numeric_limits<double>::infinity();
      mean_only = res.mean_only_offset <= kMeanOffsetSigmas;
      if (!mean_only) {
        char offset_text[64];
        std::snprintf(offset_text, sizeof offset_text, "%.3g (at most %.3g accepted)",
                      res.mean_only_offset, kMeanOffsetSigmas);
        res.mean_only_refused = "the plugin's increment_mean() is " + std::string(offset_text) +
                                " standard deviations of the prediction from the full path's "
                                "nominal increment";
        res.mean_only_offset = 0.0;
      }
    }
  }
  res.trial_path = mean_only ? "mean_only" : "full";
  // The blocks' names in the convention's order; Conclude fills their ratios.
  const auto labels = conv->order().labels();
  for (int b = 0; b < kBlockCount; ++b) res.blocks.push_back(BlockRatio{labels[b], 0.0, {}});

  // Per-sample white-noise and per-step walk standard deviations, computed once.
  std::vector<double> white_dt(K + 1), step_dt(K);
  for (std::size_t k = 0; k < K; ++k) step_dt[k] = z[k + 1].t - z[k].t;
  for (std::size_t k = 0; k <= K; ++k) {
    switch (cells) {
      case SampleCells::kForward:
      default:
        white_dt[k] = step_dt[std::min(k, K - 1)];
        break;
      case SampleCells::kBackward:
        white_dt[k] = step_dt[k == 0 ? 0 : k - 1];
        break;
      case SampleCells::kCentered:
        white_dt[k] = 0.5 * ((k == 0 ? 0.0 : step_dt[k - 1]) + (k == K ? 0.0 : step_dt[k]));
        break;
    }
  }
  // Standard deviations of the white noise on each sample and of each step's walk increment.
  const double s = options.noise_scale;
  const ImuNoise& q = input.noise;
  std::vector<double> sd_gyro(K + 1), sd_accel(K + 1), sd_walk_g(K), sd_walk_a(K);
  for (std::size_t k = 0; k <= K; ++k) {
    const double white = per_sample_std ? 1.0 : 1.0 / std::sqrt(white_dt[k]);
    sd_gyro[k] = s * q.gyro_noise_density * white;
    sd_accel[k] = s * q.accel_noise_density * white;
    if (k < K) {
      sd_walk_g[k] = s * q.gyro_random_walk * std::sqrt(step_dt[k]);
      sd_walk_a[k] = s * q.accel_random_walk * std::sqrt(step_dt[k]);
    }
  }

  errors.assign(static_cast<std::size_t>(end - first), Vec15::Zero());
  const int count = end - first;
  std::atomic<int> next{first};
  std::exception_ptr failure;
  std::mutex failure_mutex, progress_mutex;
  int done = 0;
  long long shown = -1;
  auto worker = [&] {
    std::vector<ImuSample> truth(z);
    std::vector<double> draws(6 * (K + 1) + 6 * K);  // one trial's normals
    SampleWindow window;                             // over `truth`, rebuilt per trial below
    for (int i = next++; i < end; i = next++) {
      try {
        // Trial i's own stream, from (seed, i) only: the same whatever thread runs it.
        // Per sample: white gyro and accel noise (3 + 3), then, but for the last, the walk's
        // step (3 + 3), in this order from one stream drawn at once.
        Normal(SplitMix64(SplitMix64(options.seed) ^ static_cast<std::uint64_t>(i)))
            .Fill(draws.data(), draws.size());
        const double* n = draws.data();
        auto draw3 = [&n](double sd) {
          const Vec3 v(sd * n[0], sd * n[1], sd * n[2]);
          n += 3;
          return v;
        };
        Vec3 beta_g = Vec3::Zero(), beta_a = Vec3::Zero();
        for (std::size_t k = 0; k <= K; ++k) {
          truth[k].gyro = z[k].gyro - draw3(sd_gyro[k]);
          truth[k].accel = z[k].accel - draw3(sd_accel[k]);
          if (walk_in_samples) {
            truth[k].gyro -= beta_g;
            truth[k].accel -= beta_a;
          }
          if (k < K) {
            beta_g += draw3(sd_walk_g[k]);
            beta_a += draw3(sd_walk_a[k]);
          }
        }
        // The window after the noise is drawn: it holds its first and last samples by value
        // (window.h: the boundary samples, interpolated in general), so a window made before
        // would integrate the noise-free samples 0 and K. That dropped sample 0's white noise
        // (and for centered cells sample K's as well) from every trial, until this version: a
        // variance deficit of about one step in K, (K-1)/K in theta and ((K-1)/K)^3 in p for a
        // forward method, 1/2000 on a whole 10 s case but 25 % in theta over 4 steps.
        if (!MakeWindow(truth.data(), truth.size(), truth.front().t, truth.back().t, window).ok())
          throw Error("montecarlo: cannot window the samples");
        Preintegrated m;
        if (mean_only) {
          const Status st = IncrementMean(method, window, input, m.delta);
          if (!st.ok())
            throw Error("montecarlo: trial " + std::to_string(i) + ": " + Printable(st.message()));
        } else {
          m = Preintegrate(reg, method, window, input.bg, input.ba, input.noise);
        }
        m.delta.dbg = nominal.delta.dbg + beta_g;
        m.delta.dba = nominal.delta.dba + beta_a;
        Vec15 e;
        conv->local(nominal.delta, m.delta, e);
        errors[static_cast<std::size_t>(i - first)] = e;
        if (options.progress) {
          const std::lock_guard<std::mutex> lock(progress_mutex);
          ++done;
          if (done * 100LL / count != shown) {
            shown = done * 100LL / count;
            options.progress(done, count);
          }
        }
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = end;
      }
    }
  };
  // At most kMaxThreads workers: more than the cores only adds switching, and a thread that
  // cannot be started leaves the trials to the ones that did.
  const int threads = std::max(1, std::min({options.threads, count, kMaxThreads}));
  std::vector<std::thread> pool;
  try {
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  } catch (const std::system_error&) {
  }
  worker();
  for (auto& th : pool) th.join();
  if (failure) std::rethrow_exception(failure);
  for (const Vec15& e : errors)
    if (!e.allFinite())
      throw Error("montecarlo: a trial's end error is not finite (method " + Printable(method.id) +
                  ")");
  return res;
}

void Conclude(Result& res, const std::vector<Vec15>& errors) {
  if (errors.size() != static_cast<std::size_t>(res.trials))
    throw Error("montecarlo: " + std::to_string(errors.size()) + " end errors for a run of " +
                std::to_string(res.trials) + " trials");
  for (const Vec15& e : errors)
    if (!e.allFinite())
      throw Error("montecarlo: a trial's end error is not finite (method " + Printable(res.method) +
                  ")");
  if (!ComputeStatistics(errors, res.predicted, res.stats))
    throw Error("montecarlo: the covariance " + Printable(res.method) + " predicts in " +
                Printable(res.convention) +
                " is not positive definite (are all four noise densities of the case positive?); "
                "nothing to "
                "compare the trials with");
  res.trial_nees = TrialNees(errors, res.predicted);  // for the report's histogram (trial_nees.h)

  if (res.blocks.size() != static_cast<std::size_t>(kBlockCount))
    throw Error("montecarlo: " + std::to_string(res.blocks.size()) + " block names, expected " +
                std::to_string(kBlockCount));
  for (int b = 0; b < kBlockCount; ++b) {
    BlockRatio& r = res.blocks[static_cast<std::size_t>(b)];
    const Mat3 S = res.stats.sample_cov.block<3, 3>(3 * b, 3 * b),
               P = res.predicted.block<3, 3>(3 * b, 3 * b);
    r.variance_ratio = S.trace() / P.trace();
    for (int a = 0; a < 3; ++a) r.axes[a] = S(a, a) / P(a, a);
  }

  // A statistic that is not finite (end errors near the largest double, a forged shard) is no
  // ground for a verdict: the comparisons below would all be false and read as "too large".
  const Statistics& st = res.stats;
  const auto refuse_non_finite = [&](const char* what, double x) {
    if (!std::isfinite(x))
      throw Error("montecarlo: the " + std::string(what) + " is not finite (" + std::to_string(x) +
                  ", method " + Printable(res.method) +
                  "): the trials' end errors are too large to judge; no verdict is given");
  };
  refuse_non_finite("NEES mean", st.nees_mean);
  refuse_non_finite("KL divergence", st.kl);
  refuse_non_finite("relative Frobenius difference", st.relative_frobenius);
  if (!st.sample_cov.allFinite() || !st.mean.allFinite())
    refuse_non_finite("sample covariance", std::numeric_limits<double>::quiet_NaN());
  for (const BlockRatio& b : res.blocks) {
    refuse_non_finite("variance ratio", b.variance_ratio);
    for (double r : b.axes) refuse_non_finite("variance ratio", r);
  }

  // The verdict: each test at kTestLevel, so that a right covariance is called inconsistent
  // at most kFalseAlarmRate of the time (Bonferroni; statistics.h).
  res.reasons.clear();
  const bool nees_ok = !(st.nees_p_value < kTestLevel);
  const bool kl_ok = !(st.kl_p_value < kTestLevel);
  res.verdict = nees_ok && kl_ok ? Verdict::consistent : Verdict::inconsistent;
  res.verdict_p_value = std::min(1.0, 2.0 * std::min(st.nees_p_value, st.kl_p_value));
  auto fmt = [](double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", x);
    return std::string(buf);
  };
  const std::string level = fmt(100 * kTestLevel) + "%";
  if (!nees_ok)
    res.reasons.push_back(
        "NEES mean " + fmt(st.nees_mean) + " outside its " + fmt(100 * kNeesConfidence) +
        "% chi-square bounds [" + fmt(st.nees_bounds[0]) + ", " + fmt(st.nees_bounds[1]) +
        "] (p = " + fmt(st.nees_p_value) + " < " + level + "): the predicted covariance is " +
        (st.nees_mean > st.nees_bounds[1] ? "too small" : "too large"));
  if (!kl_ok)
    res.reasons.push_back("KL divergence " + fmt(st.kl) + " above its " + fmt(100 * kKlLevel) +
                          "% bound " + fmt(st.kl_bound) + " for N = " + std::to_string(st.trials) +
                          " (p = " + fmt(st.kl_p_value) + " < " + level +
                          "): the shape of the covariance differs");
  if (nees_ok && kl_ok)
    res.reasons.push_back("NEES mean within its " + fmt(100 * kNeesConfidence) +
                          "% bounds (p = " + fmt(st.nees_p_value) +
                          ") and KL divergence below its " + fmt(100 * kKlLevel) +
                          "% bound (p = " + fmt(st.kl_p_value) + "); each test at " + level +
                          ", so a right covariance is called inconsistent at most " +
                          fmt(100 * kFalseAlarmRate) + "% of the time");
  if (st.trials < kKlChiSquareFromTrials)
    res.reasons.push_back(
        "N = " + std::to_string(st.trials) + " is below " + std::to_string(kKlChiSquareFromTrials) +
        ": the KL test's chi-square distribution is approximate there, and the false-alarm rate "
        "may exceed " +
        fmt(100 * kFalseAlarmRate) + "% (docs/montecarlo.md, \"The verdict\")");
  if (!res.noise_model.matches)
    res.reasons.push_back(
        "the simulated noise is not the model the prediction assumes (noise_model.note): the "
        "verdict judges that mismatch");
}

}  // namespace imuconv::montecarlo
