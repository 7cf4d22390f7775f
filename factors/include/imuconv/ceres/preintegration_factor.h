// The preintegration factor between two keyframes (the note, section 4.3): any propagator's or
// preintegrator's measurement as a Ceres cost, with first-order bias correction in Evaluate and
// re-integration at a moved bias between solves (VINS-Fusion's repropagate).
#pragma once

#include <ceres/cost_function.h>

#include <limits>
#include <vector>

#include "imuconv/bridge.h"
#include "imuconv/ceres/export.h"
#include "imuconv/registry.h"
#include "imuconv/types.h"

namespace imuconv::ceres_factors {

struct PreintegrationFactorOptions {
  ResidualKind kind = ResidualKind::Gtsam;  ///< bridge.h; 15 residuals [theta, p, v, bg, ba]
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  /// Re-integrate from the samples (ReintegrateIfMoved) when the start bias estimate has moved
  /// from the linearization bias by more than these (Euclidean norm of the 3-vector), as
  /// VINS-Fusion's repropagate; +infinity: first-order correction only.
  double reintegrate_gyro_bias = std::numeric_limits<double>::infinity();   // rad/s
  double reintegrate_accel_bias = std::numeric_limits<double>::infinity();  // m/s^2
};

/// Owns a copy of the samples of its window, the resolved method (any propagator --
/// preintegration by propagation, e.g. rk4 -- or a native preintegrator), the noise, and the
/// current measurement in the reference charts.
class IMUCONV_CERES_API PreintegrationFactor {
 public:
  /// Preintegrates samples over [t_s, t_e] at (bg_hat, ba_hat). Throws imuconv::Error for an
  /// interval the samples do not cover, samples out of order, a non-finite value, or a
  /// residual covariance that is not positive definite. `reg` must outlive the factor.
  PreintegrationFactor(const Registry& reg, const PreintegrationMethod& method,
                       std::vector<ImuSample> samples, double t_s, double t_e,
                       const ImuNoise& noise, const Vec3& bg_hat, const Vec3& ba_hat,
                       const PreintegrationFactorOptions& options = {});

  /// The current measurement, in the reference charts (preint_reference).
  const Preintegrated& measurement() const { return measurement_; }
  /// S with S^T S = cov(r)^{-1}: S = C^{-1}, C the lower Cholesky factor of the residual's
  /// covariance cov(r) = C C^T (so S is lower triangular). Whitened residual S r.
  const Mat15& sqrt_information() const { return sqrt_information_; }
  const PreintegrationFactorOptions& options() const { return options_; }
  const Registry& registry() const { return *reg_; }
  double t_start() const { return t_s_; }
  double t_end() const { return t_e_; }

  /// Residual (whitened, 15) and Jacobians (whitened, with respect to the left chart) at two
  /// states; `cov` is the identity's (the whitened residual's) covariance, cov(r) whitened.
  Residual Evaluate(const ImuState& x_s, const ImuState& x_e) const;
  /// Re-integrates at (bg, ba) if they moved beyond the options' thresholds; returns whether it
  /// did.
  bool ReintegrateIfMoved(const Vec3& bg, const Vec3& ba);
  /// Re-integrates at (bg, ba) unconditionally.
  void Reintegrate(const Vec3& bg, const Vec3& ba);
  /// A ceres::CostFunction (15 residuals; blocks 16, 16: start and end state) that evaluates
  /// this factor; it refers to *this, which must outlive it (Problem takes ownership of the
  /// cost only). Not to be re-integrated while a solve runs.
  ::ceres::CostFunction* MakeCostFunction() const;

 private:
  const Registry* reg_;
  PreintegrationMethod method_;
  std::vector<ImuSample> samples_;
  double t_s_, t_e_;
  ImuNoise noise_;
  PreintegrationFactorOptions options_;
  Preintegrated measurement_;
  Mat15 sqrt_information_ = Mat15::Identity();
};

}  // namespace imuconv::ceres_factors
