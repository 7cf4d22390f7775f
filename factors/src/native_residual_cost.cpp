// The ceres::CostFunction of a NativeResidualFactor: n residuals (the system's dimension), the
// factor's whitened residual and its left-chart Jacobians times M_left (state_block.h).
#include <ceres/cost_function.h>

#include "imuconv/ceres/native_residual_factor.h"
#include "imuconv/ceres/state_block.h"

namespace imuconv::ceres_factors {

namespace {

class NativeResidualCost final : public ::ceres::CostFunction {
 public:
  explicit NativeResidualCost(const NativeResidualFactor& factor) : factor_(&factor) {
    set_num_residuals(factor.dimension());
    mutable_parameter_block_sizes()->push_back(kStateBlockSize);
    mutable_parameter_block_sizes()->push_back(kStateBlockSize);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    try {
      const bool want =
          jacobians != nullptr && (jacobians[0] != nullptr || jacobians[1] != nullptr);
      NativeResidualFactor::Evaluation e;
      if (!factor_->EvaluateInto(FromStateBlock(parameters[0]), FromStateBlock(parameters[1]), want,
                                 e))
        return false;  // Ceres reports a failed evaluation (and shortens the step)
      Eigen::Map<Eigen::VectorXd>(residuals, e.whitened.size()) = e.whitened;
      if (want) {
        if (jacobians[0] != nullptr) LeftToAmbient(e.H_start, parameters[0], jacobians[0]);
        if (jacobians[1] != nullptr) LeftToAmbient(e.H_end, parameters[1], jacobians[1]);
      }
      return true;
    } catch (...) {  // no exception crosses into Ceres
      return false;
    }
  }

 private:
  const NativeResidualFactor* factor_;
};

}  // namespace

::ceres::CostFunction* NativeResidualFactor::MakeCostFunction() const {
  return new NativeResidualCost(*this);
}

}  // namespace imuconv::ceres_factors
