// VINS-Fusion's IMU factor (see imuconv/kernels/vins_fusion_residual.h for the formulas and
// the two upstream approximations kept). The quaternion operations are Eigen's, as upstream
// uses them: inverse() divides the conjugate by the squared norm, q * v applies the
// unit-quaternion rotation formula.
#include "imuconv/kernels/vins_fusion_residual.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "imuconv/so3.h"

namespace imuconv::kernels {

namespace {

constexpr int kP = 0, kTheta = 3, kV = 6, kBa = 9, kBg = 12;
// Columns of the speed-bias block [v, ba, bg].
constexpr int kSbV = 0, kSbBa = 3, kSbBg = 6;

/// Utility::deltaQ: [1, theta/2], not normalized.
Eigen::Quaterniond DeltaQ(const Vec3& theta) {
  return Eigen::Quaterniond(1.0, 0.5 * theta.x(), 0.5 * theta.y(), 0.5 * theta.z());
}

/// The 4x4 matrix of q (x) . (left product), rows and columns [w, x, y, z].
Eigen::Matrix4d LeftProduct(const Eigen::Quaterniond& q) {
  Eigen::Matrix4d L;
  L(0, 0) = q.w();
  L.block<1, 3>(0, 1) = -q.vec().transpose();
  L.block<3, 1>(1, 0) = q.vec();
  L.block<3, 3>(1, 1) = q.w() * Mat3::Identity() + so3::skew(q.vec());
  return L;
}

/// The 4x4 matrix of . (x) q (right product).
Eigen::Matrix4d RightProduct(const Eigen::Quaterniond& q) {
  Eigen::Matrix4d R;
  R(0, 0) = q.w();
  R.block<1, 3>(0, 1) = -q.vec().transpose();
  R.block<3, 1>(1, 0) = q.vec();
  R.block<3, 3>(1, 1) = q.w() * Mat3::Identity() - so3::skew(q.vec());
  return R;
}

/// The rotation rows' lower-right 3x3 of a 4x4 product matrix: d vec / d vec.
Mat3 VecBlock(const Eigen::Matrix4d& M) { return M.bottomRightCorner<3, 3>(); }

}  // namespace

VinsFusionCorrectedDelta VinsFusionCorrect(const VinsFusionMeasurement& m, const Vec3& ba,
                                           const Vec3& bg) {
  const Mat15& J = m.pre.jacobian;
  const Vec3 dba = ba - m.linearized_ba, dbg = bg - m.linearized_bg;
  VinsFusionCorrectedDelta c;
  c.delta_q = m.pre.delta_q * DeltaQ(J.block<3, 3>(kTheta, kBg) * dbg);
  c.delta_v = m.pre.delta_v + J.block<3, 3>(kV, kBa) * dba + J.block<3, 3>(kV, kBg) * dbg;
  c.delta_p = m.pre.delta_p + J.block<3, 3>(kP, kBa) * dba + J.block<3, 3>(kP, kBg) * dbg;
  return c;
}

Vec15 VinsFusionEvaluate(const VinsFusionMeasurement& m, const VinsFusionFactorState& i,
                         const VinsFusionFactorState& j) {
  const double T = m.pre.sum_dt;
  const VinsFusionCorrectedDelta c = VinsFusionCorrect(m, i.Ba, i.Bg);
  const Eigen::Quaterniond Qi_inv = i.Q.inverse();
  Vec15 r;
  r.segment<3>(kP) = Qi_inv * (0.5 * m.G * T * T + j.P - i.P - i.V * T) - c.delta_p;
  r.segment<3>(kTheta) = 2.0 * (c.delta_q.inverse() * (Qi_inv * j.Q)).vec();
  r.segment<3>(kV) = Qi_inv * (m.G * T + j.V - i.V) - c.delta_v;
  r.segment<3>(kBa) = j.Ba - i.Ba;
  r.segment<3>(kBg) = j.Bg - i.Bg;
  return r;
}

VinsFusionFactorOutput VinsFusionRawFactor(const VinsFusionMeasurement& m,
                                           const VinsFusionFactorState& i,
                                           const VinsFusionFactorState& j) {
  VinsFusionFactorOutput out;
  out.residual = VinsFusionEvaluate(m, i, j);
  const double T = m.pre.sum_dt;
  const Mat15& J = m.pre.jacobian;
  const Eigen::Quaterniond Qi_inv = i.Q.inverse();
  const Mat3 Ri_T = Qi_inv.toRotationMatrix();
  const Eigen::Quaterniond c_q = VinsFusionCorrect(m, i.Ba, i.Bg).delta_q;
  const Mat3 I = Mat3::Identity();

  out.jacobian_pose_i.block<3, 3>(kP, kP) = -Ri_T;
  out.jacobian_pose_i.block<3, 3>(kP, kTheta) =
      so3::skew(Qi_inv * (0.5 * m.G * T * T + j.P - i.P - i.V * T));
  out.jacobian_pose_i.block<3, 3>(kTheta, kTheta) =
      -VecBlock(LeftProduct(j.Q.inverse() * i.Q) * RightProduct(c_q));
  out.jacobian_pose_i.block<3, 3>(kV, kTheta) = so3::skew(Qi_inv * (m.G * T + j.V - i.V));

  Mat15x9& sb_i = out.jacobian_speedbias_i;
  sb_i.block<3, 3>(kP, kSbV) = -Ri_T * T;
  sb_i.block<3, 3>(kP, kSbBa) = -J.block<3, 3>(kP, kBa);
  sb_i.block<3, 3>(kP, kSbBg) = -J.block<3, 3>(kP, kBg);
  // Upstream's choice, kept: the uncorrected delta_q (header).
  sb_i.block<3, 3>(kTheta, kSbBg) =
      -VecBlock(LeftProduct(j.Q.inverse() * i.Q * m.pre.delta_q)) * J.block<3, 3>(kTheta, kBg);
  sb_i.block<3, 3>(kV, kSbV) = -Ri_T;
  sb_i.block<3, 3>(kV, kSbBa) = -J.block<3, 3>(kV, kBa);
  sb_i.block<3, 3>(kV, kSbBg) = -J.block<3, 3>(kV, kBg);
  sb_i.block<3, 3>(kBa, kSbBa) = -I;
  sb_i.block<3, 3>(kBg, kSbBg) = -I;

  out.jacobian_pose_j.block<3, 3>(kP, kP) = Ri_T;
  out.jacobian_pose_j.block<3, 3>(kTheta, kTheta) =
      VecBlock(LeftProduct(c_q.inverse() * Qi_inv * j.Q));

  out.jacobian_speedbias_j.block<3, 3>(kV, kSbV) = Ri_T;
  out.jacobian_speedbias_j.block<3, 3>(kBa, kSbBa) = I;
  out.jacobian_speedbias_j.block<3, 3>(kBg, kSbBg) = I;
  return out;
}

Status VinsFusionSqrtInfo(const Mat15& covariance, Mat15& sqrt_info) {
  // The same two factorizations as upstream (partial-pivoting LU for the inverse, then LLT),
  // so that the ill-conditioned step rounds the same way.
  const Eigen::LLT<Mat15> llt(covariance.inverse());
  sqrt_info = llt.matrixL().transpose();
  if (llt.info() != Eigen::Success || !covariance.allFinite() || !sqrt_info.allFinite())
    return Status::Error(
        "the covariance is singular or not positive definite (is a noise density zero?): it has no "
        "square-root "
        "information");
  return Status::Ok();
}

VinsFusionFactorOutput VinsFusionWhiten(const VinsFusionFactorOutput& raw, const Mat15& sqrt_info) {
  VinsFusionFactorOutput w;
  w.residual = sqrt_info * raw.residual;
  w.jacobian_pose_i = sqrt_info * raw.jacobian_pose_i;
  w.jacobian_pose_j = sqrt_info * raw.jacobian_pose_j;
  w.jacobian_speedbias_i = sqrt_info * raw.jacobian_speedbias_i;
  w.jacobian_speedbias_j = sqrt_info * raw.jacobian_speedbias_j;
  return w;
}

}  // namespace imuconv::kernels
