// The ceres::CostFunction of a PreintegrationFactor: the factor's whitened residual, and its
// left-chart Jacobians times M_left (state_block.h) as the ambient Jacobians Ceres asks for.
#include <ceres/sized_cost_function.h>

#include "imuconv/ceres/preintegration_factor.h"
#include "imuconv/ceres/state_block.h"

namespace imuconv::ceres_factors {

namespace {

class PreintegrationCost final
    : public ::ceres::SizedCostFunction<15, kStateBlockSize, kStateBlockSize> {
 public:
  explicit PreintegrationCost(const PreintegrationFactor& factor) : factor_(&factor) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    try {
      // The bridge's residual in the left chart, whitened by the factor's fixed S (lower
      // triangular); the residual's covariance and H_increment, which ComputeResidual also
      // returns, are not needed here (PreintegrationFactor::Evaluate whitens them too).
      const PreintegrationFactorOptions& o = factor_->options();
      const Residual r = ComputeResidual(factor_->registry(), o.kind, factor_->measurement(),
                                         FromStateBlock(parameters[0]),
                                         FromStateBlock(parameters[1]), "left", o.gravity);
      const auto S = factor_->sqrt_information().triangularView<Eigen::Lower>();
      const Vec15 whitened = S * r.r;
      if (!whitened.allFinite()) return false;
      Eigen::Map<Vec15> residuals_out(residuals);
      residuals_out = whitened;
      if (jacobians != nullptr) {
        if (jacobians[0] != nullptr) {
          const Mat15 H = S * r.H_start;
          LeftToAmbient(H, parameters[0], jacobians[0]);
        }
        if (jacobians[1] != nullptr) {
          const Mat15 H = S * r.H_end;
          LeftToAmbient(H, parameters[1], jacobians[1]);
        }
      }
      return true;
    } catch (...) {
      // Ceres reports a failed evaluation (and shortens the step); no exception crosses it.
      return false;
    }
  }

 private:
  const PreintegrationFactor* factor_;
};

}  // namespace

::ceres::CostFunction* PreintegrationFactor::MakeCostFunction() const {
  return new PreintegrationCost(*this);
}

}  // namespace imuconv::ceres_factors
