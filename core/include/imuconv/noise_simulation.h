// What a propagation or preintegration scheme assumes of the noise on its samples, given by
// its plugin as plain data (Propagator::noise_simulation(), Preintegrator::noise_simulation()),
// so that a host can draw the noise the scheme's covariance integrates (imuconv montecarlo,
// docs/montecarlo.md) without knowing the scheme by name.
//
// The white noise of the note's section 2.1 is a continuous process; a scheme integrates each
// sample over its cell, the part of the interval it weights that sample over. Drawing each
// sample's noise as N(0, sigma^2/dt_k) with dt_k the length of its cell makes the weighted sum
// of the sample noises the integral of one continuous white noise over the interval (the
// cells partition [t_s, t_e]). Which cells a scheme has is a fact of its arithmetic, and how it
// reads the four noise numbers a fact of its noise mapping: both belong to the plugin.
#pragma once

namespace imuconv {

/// The cell each sample k of a window is weighted over, h_k being the step t_k -> t_k+1.
enum class SampleCells : int {
  kForward = 0,   ///< held over the step it starts, [t_k, t_k+1]: dt_k = h_k
  kBackward = 1,  ///< held over the step that ends at it, [t_k-1, t_k]: dt_k = h_k-1
  /// Half of each step beside it, [t_k - h_k-1/2, t_k + h_k/2] (half cells at the two ends):
  /// schemes that average the two ends of a step or interpolate linearly between knots, whose
  /// rotation increment weighs sample k by the trapezoid weight (h_k-1 + h_k)/2.
  kCentered = 2,
};

/// How a scheme reads the case's four noise numbers (ImuNoise).
enum class NoiseReading : int {
  /// Continuous densities: white noise sigma^2/dt_k on each sample, and a bias random walk
  /// sigma_b^2 h_k per step that the samples carry (the note, section 2.1).
  kContinuous = 0,
  /// Continuous densities; the bias walk only in the increment's bias entries: the samples are
  /// integrated at the constant bias estimate, as a scheme that holds the bias constant over the
  /// interval assumes.
  kWalkInIncrementOnly = 1,
  /// The two white-noise numbers as per-sample standard deviations (not divided by sqrt dt);
  /// the bias walk, from densities, as kWalkInIncrementOnly.
  kPerSampleStd = 2,
};

/// A scheme's noise, as plain data across the plugin boundary. The default is what a plugin
/// that says nothing gets: forward cells, continuous densities.
struct NoiseSimulation {
  SampleCells cells = SampleCells::kForward;
  NoiseReading reading = NoiseReading::kContinuous;
  /// false: no noise drawn per sample reproduces what the scheme's covariance assumes (e.g. it
  /// takes the two ends of a step as independent); a host that simulates `reading` anyway says
  /// that its verdict measures that mismatch, and `note` says what it is.
  bool simulable = true;
  /// Appended verbatim to the host's description of `reading`: why the scheme reads the noise
  /// so (its docs page), and for simulable = false the mismatch. Never null; a string of static
  /// storage duration in the plugin (valid while the plugin is loaded).
  const char* note = "";
};

}  // namespace imuconv
