// Preintegrator: a native preintegration scheme (paper, eq. Preint):
//   Preint: [b_s, z_{s:e}, q] -> [Delta x_se, J_bs, Sigma_Delta x].
// It reports its covariance in cov_convention() and its bias Jacobian in the chart of
// jacobian_convention(), both ids of registered preintegration conventions.
#pragma once

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

struct NativePreintegration {
  double dt = 0.0;
  PreintIncrement delta;
  Vec3 bg_hat = Vec3::Zero(), ba_hat = Vec3::Zero();
  /// 15x15 covariance of the increment (bias random walk included) in cov_convention().
  Mat15 cov = Mat15::Zero();
  /// Rows: the (theta, p, v) rows of jacobian_convention()'s chart, in its block order.
  /// Columns: an additive change of the bias estimate, in that convention's bias order.
  Mat96 J_bias = Mat96::Zero();
};

class Preintegrator {
 public:
  virtual ~Preintegrator() = default;
  virtual const char* id() const noexcept = 0;
  virtual const char* cov_convention() const noexcept = 0;
  virtual const char* jacobian_convention() const noexcept = 0;
  virtual Status integrate(const PreintegrationInput& in, NativePreintegration& out) const noexcept = 0;
};

}  // namespace imuconv
