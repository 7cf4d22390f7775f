// A pose measurement of one state: r = [Log(R_meas^T R) / sigma_rot; (p - p_meas) / sigma_pos].
#include <ceres/sized_cost_function.h>

#include <Eigen/Geometry>
#include <cmath>

#include "imuconv/ceres/pose_factors.h"
#include "imuconv/ceres/state_block.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace imuconv::ceres_factors {

namespace {

class PoseMeasurement final : public ::ceres::SizedCostFunction<6, kStateBlockSize> {
 public:
  PoseMeasurement(const Mat3& R_meas, const Vec3& p_meas, double sigma_pos, double sigma_rot)
      : R_meas_(R_meas), p_meas_(p_meas), sigma_pos_(sigma_pos), sigma_rot_(sigma_rot) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const ImuState x = FromStateBlock(parameters[0]);
    const Vec3 phi = so3::Log(R_meas_.transpose() * x.R);
    Eigen::Map<Eigen::Matrix<double, 6, 1>> r(residuals);
    r << phi / sigma_rot_, (x.p - p_meas_) / sigma_pos_;
    if (!r.allFinite()) return false;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      // Left chart: R = Exp(e) R gives R_meas^T R Exp(R^T e), so d phi / d e = Jr^{-1}(phi) R^T.
      Eigen::Matrix<double, 6, 15> H = Eigen::Matrix<double, 6, 15>::Zero();
      H.block<3, 3>(0, left_idx::theta) = so3::JrInv(phi) * x.R.transpose() / sigma_rot_;
      H.block<3, 3>(3, left_idx::p) = Mat3::Identity() / sigma_pos_;
      Eigen::Map<Eigen::Matrix<double, 6, kStateBlockSize, Eigen::RowMajor>> jacobians_0_out(
          jacobians[0]);
      jacobians_0_out = H * LeftMinusJacobian(parameters[0]);
    }
    return true;
  }

 private:
  Mat3 R_meas_;
  Vec3 p_meas_;
  double sigma_pos_, sigma_rot_;
};

}  // namespace

::ceres::CostFunction* MakePoseMeasurement(const Mat3& R_meas, const Vec3& p_meas,
                                           double sigma_pos_m, double sigma_rot_rad) {
  if (!std::isfinite(sigma_pos_m) || !(sigma_pos_m > 0.0) || !std::isfinite(sigma_rot_rad) ||
      !(sigma_rot_rad > 0.0))
    throw Error("pose measurement: sigma_pos and sigma_rot must be positive and finite");
  // Orthonormal to 1e-6 (a rotation written with 7 or more significant digits), determinant +1.
  if (!R_meas.allFinite() ||
      (R_meas.transpose() * R_meas - Mat3::Identity()).cwiseAbs().maxCoeff() >= 1e-6 ||
      !(R_meas.determinant() > 0.0))
    throw Error("pose measurement: R_meas is not a rotation matrix");
  if (!p_meas.allFinite()) throw Error("pose measurement: p_meas is not finite");
  // The nearest rotation, so that Log sees an exact one.
  const Mat3 R = Eigen::Quaterniond(R_meas).normalized().toRotationMatrix();
  return new PoseMeasurement(R, p_meas, sigma_pos_m, sigma_rot_rad);
}

}  // namespace imuconv::ceres_factors
