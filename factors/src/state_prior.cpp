// A prior on one state in a named convention's chart: r = S local_C(x_prior, x).
#include <ceres/sized_cost_function.h>

#include <memory>
#include <string>

#include "imuconv/ceres/pose_factors.h"
#include "imuconv/ceres/state_block.h"
#include "imuconv/numeric.h"
#include "imuconv/reference_charts.h"
#include "sqrt_information.h"

namespace imuconv::ceres_factors {

namespace {

class StatePrior final : public ::ceres::SizedCostFunction<15, kStateBlockSize> {
 public:
  StatePrior(std::shared_ptr<const StateConvention> chart, const ImuState& x_prior, const Mat15& S)
      : chart_(std::move(chart)), x_prior_(x_prior), S_(S) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const ImuState x = FromStateBlock(parameters[0]);
    Vec15 d;
    chart_->local(x_prior_, x, d);
    if (!d.allFinite()) return false;
    Eigen::Map<Vec15> residuals_out(residuals);
    residuals_out = S_ * d;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      // d local_C(x_prior, retract_left(x, e)) / d e at e = 0. A plugin gives its chart's
      // Jacobians only at the chart's own origin (x_prior = x), not this derivative away from it,
      // so it is Ridders' extrapolation of central differences of the plugin's own local and the
      // reference retract (numeric.h: ~1e-12 relative on smooth maps), which costs about 300
      // chart evaluations; a prior is one cost per problem.
      const Mat15 H_left = RiddersJacobian([&](const Vec15& e, Vec15& out) {
        ImuState y;
        LeftRetract(x, e, y);
        chart_->local(x_prior_, y, out);
      });
      if (!H_left.allFinite()) return false;
      Eigen::Map<Eigen::Matrix<double, 15, kStateBlockSize, Eigen::RowMajor>> jacobians_0_out(
          jacobians[0]);
      jacobians_0_out = S_ * H_left * LeftMinusJacobian(parameters[0]);
    }
    return true;
  }

 private:
  std::shared_ptr<const StateConvention> chart_;
  ImuState x_prior_;
  Mat15 S_;
};

bool IsRotation(const Mat3& R) {
  // Orthonormal to 1e-6: a rotation read from a text file with 7 or more significant digits
  // passes; anything else (a scaled matrix, a reflection) is not a rotation.
  return R.allFinite() && (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-6 &&
         R.determinant() > 0.0;
}

}  // namespace

::ceres::CostFunction* MakeStatePrior(const Registry& reg, std::string_view convention,
                                      const ImuState& x_prior, const Mat15& cov) {
  std::shared_ptr<const StateConvention> chart = reg.state_convention(convention);
  if (!IsRotation(x_prior.R) || !x_prior.p.allFinite() || !x_prior.v.allFinite() ||
      !x_prior.bg.allFinite() || !x_prior.ba.allFinite())
    throw Error("state prior: the prior state is not finite or its R is not a rotation");
  const std::string problem = CovarianceProblem(cov);
  if (!problem.empty()) throw Error("state prior: the covariance: " + problem);
  Mat15 S;  // S^T S = cov^{-1}
  const detail::SqrtInformationStatus status =
      detail::InverseCholeskyFactor(Mat15(0.5 * (cov + cov.transpose())), S);
  if (status == detail::SqrtInformationStatus::kNotPositiveDefinite)
    throw Error("state prior: the covariance is not positive definite");
  if (status == detail::SqrtInformationStatus::kNearSingular)
    throw Error("state prior: the covariance is too close to singular");
  ImuState x = x_prior;
  Eigen::Quaterniond q(x.R);
  x.R = q.normalized().toRotationMatrix();
  return new StatePrior(std::move(chart), x, S);
}

}  // namespace imuconv::ceres_factors
