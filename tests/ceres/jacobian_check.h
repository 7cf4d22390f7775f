// The derivative check every cost of imuconv::ceres passes, along Ceres's own path: the cost's
// ambient Jacobian times the manifold's PlusJacobian against central differences of the cost
// through the manifold's Plus, block by block.
#pragma once

#include <ceres/ceres.h>

#include <algorithm>
#include <vector>

#include <Eigen/Core>

namespace imuconv::ceres_test {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Per block b and tangent column i, |analytic - numeric| of that column divided by the largest
/// entry of block b's differences (at least 1); steps[b][i] is the step of column i.
inline std::vector<Eigen::VectorXd> TangentJacobianColumnErrors(
    const ::ceres::CostFunction& cost, const std::vector<double*>& blocks,
    const std::vector<const ::ceres::Manifold*>& manifolds,
    const std::vector<Eigen::VectorXd>& steps) {
  const int m = cost.num_residuals();
  const std::vector<int32_t>& sizes = cost.parameter_block_sizes();
  std::vector<RowMatrix> ambient(blocks.size());
  std::vector<double*> jac(blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    ambient[b].resize(m, sizes[b]);
    jac[b] = ambient[b].data();
  }
  std::vector<Eigen::VectorXd> errors(blocks.size());
  Eigen::VectorXd r0(m);
  if (!cost.Evaluate(blocks.data(), r0.data(), jac.data())) {
    for (std::size_t b = 0; b < blocks.size(); ++b)
      errors[b] = Eigen::VectorXd::Constant(manifolds[b]->TangentSize(), 1e300);
    return errors;
  }
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const ::ceres::Manifold& M = *manifolds[b];
    RowMatrix P(M.AmbientSize(), M.TangentSize());
    M.PlusJacobian(blocks[b], P.data());
    const RowMatrix analytic = ambient[b] * P;
    RowMatrix numeric(m, M.TangentSize());
    std::vector<double> saved(blocks[b], blocks[b] + sizes[b]), moved(sizes[b]);
    for (int i = 0; i < M.TangentSize(); ++i) {
      const double h = steps[b][i];
      Eigen::VectorXd d = Eigen::VectorXd::Zero(M.TangentSize()), rp(m), rm(m);
      d[i] = h;
      M.Plus(saved.data(), d.data(), moved.data());
      std::copy(moved.begin(), moved.end(), blocks[b]);
      cost.Evaluate(blocks.data(), rp.data(), nullptr);
      d[i] = -h;
      M.Plus(saved.data(), d.data(), moved.data());
      std::copy(moved.begin(), moved.end(), blocks[b]);
      cost.Evaluate(blocks.data(), rm.data(), nullptr);
      numeric.col(i) = (rp - rm) / (2.0 * h);
    }
    std::copy(saved.begin(), saved.end(), blocks[b]);
    const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
    errors[b] = (analytic - numeric).cwiseAbs().colwise().maxCoeff().transpose() / scale;
  }
  return errors;
}

/// The largest difference between the two, divided by the largest entry of the differences
/// (at least 1), over every block. The step h = 1e-6 of the tangent: central differences err by
/// O(h^2) times the third derivative and by the residual's round-off (1e-16 |r|) over h.
inline double TangentJacobianError(const ::ceres::CostFunction& cost,
                                   const std::vector<double*>& blocks,
                                   const std::vector<const ::ceres::Manifold*>& manifolds) {
  std::vector<Eigen::VectorXd> steps;
  for (const ::ceres::Manifold* M : manifolds)
    steps.push_back(Eigen::VectorXd::Constant(M->TangentSize(), 1e-6));
  double worst = 0.0;
  for (const Eigen::VectorXd& e : TangentJacobianColumnErrors(cost, blocks, manifolds, steps))
    worst = std::max(worst, e.maxCoeff());
  return worst;
}

}  // namespace imuconv::ceres_test
