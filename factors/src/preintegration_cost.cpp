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
      const Residual r =
          factor_->Evaluate(FromStateBlock(parameters[0]), FromStateBlock(parameters[1]));
      if (!r.r.allFinite()) return false;
      Eigen::Map<Vec15> residuals_out(residuals);
      residuals_out = r.r;
      using Jacobian = Eigen::Matrix<double, 15, kStateBlockSize, Eigen::RowMajor>;
      if (jacobians != nullptr) {
        if (jacobians[0] != nullptr) {
          Eigen::Map<Jacobian> start_out(jacobians[0]);
          start_out = r.H_start * LeftMinusJacobian(parameters[0]);
        }
        if (jacobians[1] != nullptr) {
          Eigen::Map<Jacobian> end_out(jacobians[1]);
          end_out = r.H_end * LeftMinusJacobian(parameters[1]);
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
