// StateManifold: Plus and Minus are the convention's own retract and local; the Jacobians pass
// through the reference chart `left`, whose ambient Jacobians are analytic (state_block.cpp)
// and whose conversion to the convention the registry gives (analytic where the plugin has it,
// verified at load; Ridders' differences otherwise).
#include "imuconv/ceres/state_manifold.h"

#include "imuconv/ceres/state_block.h"

namespace imuconv::ceres_factors {

StateManifold::StateManifold(const Registry& reg, std::string_view convention)
    : reg_(&reg), id_(convention), chart_(reg.state_convention(convention)) {}

bool StateManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  ImuState y;
  chart_->retract(FromStateBlock(x), Eigen::Map<const Vec15>(delta), y);
  ToStateBlock(y, x_plus_delta);
  return true;
}

bool StateManifold::PlusJacobian(const double* x, double* jacobian) const {
  // P_left(x) J_left_C(x): d retract_C(x, d) / d d = d retract_left(x, e) / d e * d e / d d.
  const Mat15 J_left_C = reg_->to_reference<ImuState>(id_, FromStateBlock(x));
  Eigen::Map<Eigen::Matrix<double, 16, 15, Eigen::RowMajor>> jacobian_out(jacobian);
  jacobian_out = LeftPlusJacobian(x) * J_left_C;
  return true;
}

bool StateManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Vec15 d;
  chart_->local(FromStateBlock(x), FromStateBlock(y), d);
  Eigen::Map<Vec15> y_minus_x_out(y_minus_x);
  y_minus_x_out = d;
  return true;
}

bool StateManifold::MinusJacobian(const double* x, double* jacobian) const {
  // J_C_left(x) M_left(x); times PlusJacobian: J_C_left M_left P_left J_left_C = I.
  const Mat15 J_C_left = reg_->from_reference<ImuState>(id_, FromStateBlock(x));
  Eigen::Map<Eigen::Matrix<double, 15, 16, Eigen::RowMajor>> jacobian_out(jacobian);
  jacobian_out = J_C_left * LeftMinusJacobian(x);
  return true;
}

}  // namespace imuconv::ceres_factors
