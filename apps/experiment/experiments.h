// The note's two experiments (section 5), over random trials (trial.h):
//   preint-by-prop: preintegration by propagation (section 3.1) with a propagator (rk4) on the
//     raw samples, against the `manifold` and `tangent` preintegrators (GTSAM's two schemes) on
//     GTSAM's mid-sample input; the bias Jacobian and the 15x15 covariance compared in GTSAM's
//     own charts, GTSAM's numbers the reference (the note's Figure 1);
//   prop-by-preint: propagation by preintegration (section 3.2, eq. prop-cov) from those two
//     preintegrators, against the propagator run from the trial's random state and covariance;
//     Phi and the propagated covariance compared in the `left` chart, the propagator the
//     reference (the note's Figure 2).
// Each comparison keeps the mean over trials of every entry's difference, the picture the
// note's heatmaps draw.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "imuconv/registry.h"
#include "trial.h"

namespace imuconv::experiment {

/// Limits: a batch of trials is held at once (each a few tens of kB); 10^5 trials of 10 s
/// take hours already.
constexpr int kMaxTrials = 100000;
constexpr int kMaxThreads = 256;

/// What the preintegrators are fed: GTSAM's `mid` input (the note's comparison) or the raw
/// samples held (`zoh`, GTSAM fed each sample over the step it starts).
enum class PreintegratorInput { mid, zoh };

struct Options {
  bool preint_by_prop = true;
  bool prop_by_preint = true;
  int trials = 100;
  std::uint64_t seed = 1;
  int threads = 1;
  TrialSpec spec;
  std::string propagator = "rk4";
  PreintegratorInput input = PreintegratorInput::mid;
  /// The propagator is fed the raw samples with `propagator_substeps` - 1 linearly
  /// interpolated knots inserted per step (trial.h, Subdivide): for rk4 the same input
  /// integrated with a smaller step.
  int propagator_substeps = 1;
};

/// One compared matrix of one experiment, over all trials.
struct Comparison {
  std::string experiment;     ///< "preint-by-prop" or "prop-by-preint"
  std::string preintegrator;  ///< "manifold" or "tangent"
  std::string matrix;         ///< "J_bias", "cov" (of the increment or of the end state), "Phi"
  std::string reference;      ///< what d is relative to: the preintegrator or the propagator id
  std::string chart;          ///< the convention the matrices are compared in
  std::vector<std::string> row_blocks, col_blocks;  ///< block labels of the rows and columns
  std::string scaled_metric;  ///< "correlation" (covariances) or "relative_above_floor"
  /// Mean over trials of each entry's difference: the note's d, and the scale-aware d of
  /// `imuconv check` (imuconv/check/difference.h).
  Eigen::MatrixXd mean_note_d, mean_scaled_d;
  /// Over trials and entries.
  double note_mean = 0.0, note_max = 0.0, scaled_mean = 0.0, scaled_max = 0.0;
  int worst_trial = 0;  ///< the trial holding scaled_max
};

struct Result {
  Options options;
  std::vector<Comparison> comparisons;  ///< Figure 1's four, then Figure 2's four
};

/// Runs the trials on options.threads workers. Trial i depends on (seed, i) only and the
/// sums run in trial order, so the result is the same bit for bit for any thread count.
/// Throws imuconv::Error for an unknown propagator, missing preintegrators or a failed trial
/// (naming it).
Result RunExperiments(const Registry& reg, const Options& options);

}  // namespace imuconv::experiment
