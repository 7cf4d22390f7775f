// Propagator: one IMU integrator (paper, eq. prop):
//   Prop: [x_s, I, Sigma_s, z_{s:e}] -> [x_{e|s}, Phi(t_e, t_s), Sigma_{e|s}].
// Called once per interval, never once per sample. It works in its own native error-state
// convention, declared by native_convention(); the registry converts to any other.
#pragma once

#include "imuconv/increment_mean.h"
#include "imuconv/noise_simulation.h"
#include "imuconv/preintegrator.h"
#include "imuconv/status.h"
#include "imuconv/types.h"
#include "imuconv/window.h"

namespace imuconv {

struct PropagationInput {
  ImuState x_s;
  Mat15 cov_s = Mat15::Zero();  ///< start covariance in the native convention
  ImuNoise noise;
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  SampleWindow window;
};

/// The start of preintegration by propagation (the note, section 3.1): the identity with the
/// bias estimate, zero covariance and zero gravity, so that the end state is the increment
/// itself (eq. prop-by-int-rot..b with R_s = I, p_s = v_s = 0, g = 0).
inline PropagationInput PreintegrationByPropagationStart(const SampleWindow& window, const Vec3& bg,
                                                         const Vec3& ba, const ImuNoise& noise) {
  PropagationInput in;
  in.x_s.bg = bg;
  in.x_s.ba = ba;
  in.cov_s.setZero();
  in.noise = noise;
  in.gravity.setZero();
  in.window = window;
  return in;
}

struct PropagationResult {
  ImuState x_e;
  Mat15 Phi = Mat15::Identity();  ///< d dx_e / d dx_s in the native convention
  Mat15 cov = Mat15::Zero();      ///< Sigma_{e|s} in the native convention
};

class Propagator {
 public:
  virtual ~Propagator() = default;
  virtual const char* id() const noexcept = 0;
  virtual const char* native_convention() const noexcept = 0;
  virtual Status propagate(const PropagationInput& in, PropagationResult& out) const noexcept = 0;

  /// Optional (increment_mean.h): the increment alone that preintegration by propagation of
  /// `in` gives, i.e. the end state of propagate(PreintegrationByPropagationStart(in.window,
  /// in.bg, in.ba, in.noise)) as dR, dp, dv, with dbg = dba = 0. Checks its input as
  /// propagate() does. Default: IncrementMeanNotProvided().
  virtual Status increment_mean(const PreintegrationInput& in,
                                PreintIncrement& delta) const noexcept {
    (void)in;
    delta = PreintIncrement();
    return IncrementMeanNotProvided();
  }
  /// How the scheme weights its samples and reads the noise (noise_simulation.h). Default:
  /// forward cells, continuous densities.
  virtual NoiseSimulation noise_simulation() const noexcept { return NoiseSimulation(); }
};

}  // namespace imuconv
