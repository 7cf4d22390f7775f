// One random trial of the note's experiments (section 5): IMU data of a smooth random motion,
// the noise densities, and a random start state with a start covariance. Trial i is drawn from
// (seed, i) alone, so a run's numbers do not depend on how trials are spread over threads.
#pragma once

#include <cstdint>
#include <vector>

#include "imuconv/types.h"
#include "refcase.h"

namespace imuconv::experiment {

/// How the trials are sampled: the note's 10 s at 200 Hz by default.
struct TrialSpec {
  double rate_hz = 200.0;
  double duration_s = 10.0;
};

struct Trial {
  std::vector<ImuSample> samples;  ///< rate * duration + 1 knots, t from 0
  ImuNoise noise;                  ///< continuous densities
  ImuState x_s;  ///< start state; its biases are also the preintegration's bias estimate
  Mat15 cov_s_left = Mat15::Zero();  ///< start covariance in `left`, [p, theta, v, bg, ba]
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
};

/// Draws trial `index` of the run seeded `seed`, the way tests/data/reference/cases were made
/// (the `smooth` kind of ../shared/reference/gen_cases.py): per axis three sinusoids of random
/// frequency (0.05 to 2 Hz), phase and amplitude, gyro up to ~1 rad/s and specific force up to
/// ~3 m/s^2 about a random 9.81 m/s^2 gravity reaction, plus a constant offset; log-uniform
/// noise densities; a random state and a random correlated start covariance with standard
/// deviations 10 m, 0.3 rad, 3 m/s, 0.01 rad/s, 0.1 m/s^2. The signal is a function of time,
/// so a spec with a higher rate samples the same motion more densely.
Trial MakeTrial(std::uint64_t seed, std::uint64_t index, const TrialSpec& spec);

/// GTSAM's `mid` input, as the reference cases feed it (refcase.h): the experiment's
/// preintegrators see the samples the cases' mid.* results are made from.
using refcase::MidSampleInput;

/// The same piecewise-linear signal with `factor` - 1 linearly interpolated knots inserted in
/// every step: an integrator that interpolates linearly (rk4) sees the same input with a step
/// `factor` times smaller.
std::vector<ImuSample> Subdivide(const std::vector<ImuSample>& samples, int factor);

}  // namespace imuconv::experiment
