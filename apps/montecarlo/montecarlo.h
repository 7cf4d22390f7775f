// imuconv montecarlo: N noisy re-integrations of a case's samples with one preintegration
// method, their end errors in an increment convention against the covariance the method
// predicts (docs/montecarlo.md). The statistics are statistics.h; this is the simulation.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "imuconv/bridge.h"
#include "imuconv/registry.h"
#include "statistics.h"

namespace imuconv::montecarlo {

/// What the simulation draws, and whether that is what the method's covariance assumes.
struct NoiseModel {
  /// "continuous": white noise N(0, sigma^2/dt) on every sample, and a bias random walk
  /// (N(0, sigma_b^2 dt) per step) folded into the samples and into the increment's bias.
  /// "basalt": the same white noise; the walk only in the increment's bias entries, not in the
  /// samples (Basalt's preintegration keeps the bias constant over the interval, docs/basalt.md).
  /// "basalt_per_sample": as "basalt", with the white-noise numbers taken as per-sample standard
  /// deviations, as basalt_as_configured reads them.
  std::string simulated;
  bool matches = true;  ///< false: the verdict measures the mismatch, `note` says which
  std::string note;     ///< one sentence on the model (and on a mismatch, why)
};

/// The model simulated for a method: what its plugin's noise_simulation() says
/// (core/include/imuconv/noise_simulation.h).
NoiseModel NoiseModelFor(const PreintegrationMethod& method);

/// Limits: trials keep one 15-vector each (10^7 trials: 1.2 GB), threads are capped.
constexpr int kMaxTrials = 10000000;
constexpr int kMaxThreads = 256;

struct Options {
  int trials = 1000;
  std::uint64_t seed = 1;
  int threads = 1;
  double noise_scale = 1.0;  ///< densities of the simulation only (the prediction keeps the case's)
  /// false: every trial runs the method's full preintegration, even where its plugin would
  /// give its mean alone (increment_mean()) (the two are compared by tests/montecarlo/paths.cpp).
  bool allow_mean_only = true;
  /// Called with (trials done, trials) from the worker that finished a trial, under a lock, at
  /// most once per percent; it only reports (the results do not depend on it).
  std::function<void(int, int)> progress;
};

struct Input {
  std::vector<ImuSample> samples;             ///< the knots integrated (strictly increasing times)
  Vec3 bg = Vec3::Zero(), ba = Vec3::Zero();  ///< bias estimate
  ImuNoise noise;                             ///< continuous densities, as the method is given them
};

enum class Verdict { consistent, inconsistent };

struct BlockRatio {
  std::string block;             ///< "theta", "p", ... in the convention's order
  double variance_ratio = 0.0;   ///< trace of the sample block / trace of the predicted one
  std::array<double, 3> axes{};  ///< per axis, sample variance / predicted variance
};

struct Result {
  std::string method, method_kind, convention;
  int trials = 0;
  std::uint64_t seed = 0;
  double noise_scale = 1.0;
  double duration = 0.0;
  std::size_t samples = 0;
  NoiseModel noise_model;
  Statistics stats;
  Mat15 predicted = Mat15::Zero();
  std::vector<BlockRatio> blocks;
  Verdict verdict = Verdict::inconsistent;
  /// Bonferroni-adjusted p-value of the verdict, min(1, 2 min(nees_p_value, kl_p_value)): the
  /// verdict is inconsistent when it is below kFalseAlarmRate.
  double verdict_p_value = 1.0;
  std::vector<std::string> reasons;  ///< why the verdict, in words
  /// Each trial's NEES e_i^T Sigma^-1 e_i under the predicted covariance, in trial order (set by
  /// Conclude; the report's histogram against chi-square(15)).
  std::vector<double> trial_nees;
  /// How each trial was integrated: "mean_only" (the mean alone, by the method's plugin's
  /// increment_mean()) or "full" (the method's whole preintegration); docs/montecarlo.md, "Speed".
  std::string trial_path;
  /// For "mean_only": how far the mean-only path's nominal increment is from the full path's,
  /// in standard deviations of the prediction (0: bit for bit the same).
  double mean_only_offset = 0.0;
  /// For "full" where the plugin gives a mean-only integration (increment_mean()): why it was
  /// not used (it failed, or its nominal increment is not the full path's); empty otherwise.
  std::string mean_only_refused;
};

/// The default scoring chart of a method: its covariance convention for a native
/// preintegrator, `preint_reference` for preintegration by propagation.
std::string DefaultConvention(const PreintegrationMethod& method);

/// Runs the Monte Carlo. Trial i draws its noise from its own generator (normal.h: xoshiro256++
/// seeded from (seed, i), ziggurat normals), so the result is the same bit for bit for any
/// thread count. Throws imuconv::Error for a predicted covariance that is not positive definite
/// or a trial that fails.
Result RunMonteCarlo(const Registry& reg, const PreintegrationMethod& method,
                     const std::string& convention, const Input& input, const Options& options);

/// Trials [first, end) of the run `options` describes (0 <= first <= end <= options.trials):
/// RunMonteCarlo's work before the statistics. The result has every field but `stats`,
/// `blocks`, `verdict` and `reasons`; `errors` gets the trials' end errors in trial order, bit
/// for bit what the whole run computes for them (trial i is seeded from (seed, i) alone). This
/// is one shard of a run split across processes (docs/montecarlo.md, "Across machines"). Throws
/// as RunMonteCarlo, and for a trial whose end error is not finite.
Result RunTrials(const Registry& reg, const PreintegrationMethod& method,
                 const std::string& convention, const Input& input, const Options& options,
                 int first, int end, std::vector<Vec15>& errors);

/// The statistics, block ratios, verdict and reasons of `res` from all of its trials' end
/// errors in trial order (`res.trials` of them): RunMonteCarlo's end, also the merge of its
/// shards. Throws imuconv::Error for a non-finite error or a prediction that is not positive
/// definite.
void Conclude(Result& res, const std::vector<Vec15>& errors);

}  // namespace imuconv::montecarlo
