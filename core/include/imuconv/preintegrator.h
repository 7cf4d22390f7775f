// Preintegrator: a native preintegration scheme (paper, eq. Preint):
//   Preint: [b_s, z_{s:e}, q] -> [Delta x_se, J_bs, Sigma_Delta x].
// It writes the numbers of a Preintegrated (preintegrated.h): its covariance in
// cov_convention() and its bias Jacobian in the chart of jacobian_convention(), both ids of
// registered preintegration conventions. It leaves the measurement's two convention labels
// alone; the host sets them from those two ids.
#pragma once

#include "imuconv/increment_mean.h"
#include "imuconv/noise_simulation.h"
#include "imuconv/preintegrated.h"
#include "imuconv/status.h"
#include "imuconv/types.h"
#include "imuconv/window.h"

namespace imuconv {

struct PreintegrationInput {
  Vec3 bg = Vec3::Zero();  ///< bias estimate used for the integration
  Vec3 ba = Vec3::Zero();
  ImuNoise noise;
  SampleWindow window;
};

/// `window` at the bias estimate (bg, ba), with `noise`: all four fields given, none left at
/// its default unnoticed. The window references its samples: they must outlive the input.
inline PreintegrationInput PreintegrationInputOf(const SampleWindow& window, const Vec3& bg,
                                                 const Vec3& ba, const ImuNoise& noise) {
  PreintegrationInput in;
  in.bg = bg;
  in.ba = ba;
  in.noise = noise;
  in.window = window;
  return in;
}

class Preintegrator {
 public:
  virtual ~Preintegrator() = default;
  virtual const char* id() const noexcept = 0;
  virtual const char* cov_convention() const noexcept = 0;
  virtual const char* jacobian_convention() const noexcept = 0;
  virtual Status integrate(const PreintegrationInput& in, Preintegrated& out) const noexcept = 0;

  /// Optional (increment_mean.h): integrate()'s increment alone (dR, dp, dv; dbg = dba = 0),
  /// without its covariance and bias Jacobian. Checks its input as integrate() does. Default:
  /// IncrementMeanNotProvided().
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
