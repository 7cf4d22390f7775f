// Propagator: one IMU integrator (paper, eq. prop):
//   Prop: [x_s, I, Sigma_s, z_{s:e}] -> [x_{e|s}, Phi(t_e, t_s), Sigma_{e|s}].
// Called once per interval, never once per sample. It works in its own native error-state
// convention, declared by native_convention(); the registry converts to any other.
#pragma once

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
};

}  // namespace imuconv
