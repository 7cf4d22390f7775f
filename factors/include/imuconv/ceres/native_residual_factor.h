// A system's own IMU factor (a residual plugin: VINS-Fusion's IMUFactor, Basalt's residual,
// OKVIS2's ImuError, ORB-SLAM3's EdgeInertial, ...) as a Ceres cost between two keyframes, on
// the measurement of a PreintegrationFactor (the same samples, method, noise, linearization
// bias and re-integration). What is system-specific -- which output is the residual, how the
// system whitens it, which state convention and column order its Jacobians are in -- is the
// plugin's own declaration (ResidualFactor::cost_spec(), residual_cost_spec.h); nothing here
// names a system.
#pragma once

#include <ceres/cost_function.h>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "imuconv/ceres/export.h"
#include "imuconv/ceres/preintegration_factor.h"
#include "imuconv/registry.h"
#include "imuconv/residual_factor.h"
#include "imuconv/types.h"

namespace imuconv::ceres_factors {

/// The residual dimension n is the system's (degrees_of_freedom()): 15 for VINS-Fusion and
/// OKVIS2, whose residuals hold the bias random walk's rows; 9 for Basalt and ORB-SLAM3, which
/// have no bias-walk rows (both weight the bias change in a separate term, which is not part
/// of this factor; the end state's biases do not enter it).
///
/// The cost is S r_sys(x_s, x_e), r_sys the plugin's residual of the measurement expressed in
/// its increment_convention() (the registry converts it), S the system's whitening, fixed per
/// measurement: read from one evaluation at the measurement's own prediction when the factor
/// is built or re-integrated (as PreintegrationFactor's). Its Jacobians are the plugin's
/// analytic ones, assembled in its declared state convention C, carried to the reference chart
/// `left` by J_{C<-left}(x) (Registry::from_reference) and to the block's ambient coordinates
/// (LeftToAmbient). They are exact where the system's are: a system's bias Jacobians are its
/// own first-order model away from the measurement's linearization bias (the kernels'
/// headers), exact at it.
class IMUCONV_CERES_API NativeResidualFactor {
 public:
  /// The registered residual plugin `residual_id`; the rest as PreintegrationFactor's
  /// (options.kind is not used; options.gravity is the plugin's gravity). Throws
  /// imuconv::Error naming the id for an unknown id (listing the known ones), a plugin that
  /// declares no cost, a declaration naming an unknown convention or outputs the plugin does not
  /// write (or writes with other sizes, or not finite), a weighting that is not positive
  /// (semi-)definite, and everything PreintegrationFactor throws. `reg` must outlive the factor.
  NativeResidualFactor(const Registry& reg, std::string_view residual_id,
                       const PreintegrationMethod& method, std::vector<ImuSample> samples,
                       double t_s, double t_e, const ImuNoise& noise, const Vec3& bg_hat,
                       const Vec3& ba_hat, const PreintegrationFactorOptions& options = {});
  /// The same with a residual factor object (e.g. one not from a plugin file), named in
  /// messages by its id().
  NativeResidualFactor(const Registry& reg, std::shared_ptr<const ResidualFactor> factor,
                       const PreintegrationMethod& method, std::vector<ImuSample> samples,
                       double t_s, double t_e, const ImuNoise& noise, const Vec3& bg_hat,
                       const Vec3& ba_hat, const PreintegrationFactorOptions& options = {});
  ~NativeResidualFactor();
  NativeResidualFactor(const NativeResidualFactor&) = delete;
  NativeResidualFactor& operator=(const NativeResidualFactor&) = delete;

  const std::string& residual_id() const { return id_; }
  /// n, the residual's dimension (the plugin's degrees_of_freedom()).
  int dimension() const;
  /// The measurement and its re-integration, in the reference charts.
  const PreintegrationFactor& preintegration() const { return preintegration_; }
  /// The measurement as the plugin receives it (in its increment_convention()).
  const Preintegrated& expressed_measurement() const;
  /// S (n x n): the whitened residual is S r_sys.
  const Eigen::MatrixXd& sqrt_information() const;

  struct Evaluation {
    Eigen::VectorXd residual;  ///< r_sys, the plugin's own residual (unwhitened), n
    Eigen::VectorXd whitened;  ///< S r_sys
    /// S d r_sys / d dx in the left chart (n x 15) at x_s and at x_e.
    Eigen::MatrixXd H_start, H_end;
  };
  /// The factor at two states; throws imuconv::Error naming the id for a failed evaluation.
  Evaluation Evaluate(const ImuState& x_s, const ImuState& x_e) const;
  /// As PreintegrationFactor's; the whitening is read again after a re-integration. If that
  /// throws, the factor is unusable: Evaluate throws and its cost fails.
  bool ReintegrateIfMoved(const Vec3& bg, const Vec3& ba);
  void Reintegrate(const Vec3& bg, const Vec3& ba);
  /// A ceres::CostFunction (n residuals; blocks 16, 16: start and end state) that evaluates
  /// this factor; it refers to *this, which must outlive it. Not to be re-integrated while a
  /// solve runs.
  ::ceres::CostFunction* MakeCostFunction() const;

  /// Evaluate() without allocating an Evaluation's Jacobians when `jacobians` is false; false
  /// for a failed evaluation (the cost's path: no exception).
  bool EvaluateInto(const ImuState& x_s, const ImuState& x_e, bool jacobians,
                    Evaluation& out) const noexcept;

 private:
  struct Native;
  /// Expresses the measurement in the plugin's increment convention and reads the whitening.
  void ReadWhitening();
  /// "" or why the plugin's evaluation failed.
  std::string EvaluateOrSay(const ImuState& x_s, const ImuState& x_e, bool jacobians,
                            Evaluation& out) const;
  std::string id_;
  PreintegrationFactor preintegration_;
  std::unique_ptr<Native> native_;
};

}  // namespace imuconv::ceres_factors
