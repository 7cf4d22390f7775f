// VINS-Fusion's IMU factor (HKUST-Aerial-Robotics/VINS-Fusion, IntegrationBase::evaluate and
// IMUFactor::Evaluate), reproduced to round-off on an IntegrationBase state
// (kernels/vins_fusion.h): the 15-vector residual, the four raw Jacobian blocks Ceres is
// given, the square-root information and the whitened outputs.
//
// Order [p, theta, v, ba, bg] (O_P = 0, O_R = 3, O_V = 6, O_BA = 9, O_BG = 12). VINS's G is
// minus the gravity vector (world acceleration = R (a - ba) - G). With T = sum_dt, J the
// IntegrationBase Jacobian product, dba = Ba_i - linearized_ba and dbg = Bg_i - linearized_bg,
// the first-order bias correction is
//   c_p = delta_p + J_p,ba dba + J_p,bg dbg,   c_v likewise,
//   c_q = delta_q (x) [1, J_theta,bg dbg / 2]     -- deltaQ, NOT normalized
// and the residual
//   r_p     = Q_i^-1 (G T^2/2 + P_j - P_i - V_i T) - c_p
//   r_theta = 2 vec(c_q^-1 (x) Q_i^-1 (x) Q_j)      -- c_q^-1 = conj(c_q)/|c_q|^2 (Eigen)
//   r_v     = Q_i^-1 (G T + V_j - V_i) - c_v
//   r_ba    = Ba_j - Ba_i,   r_bg = Bg_j - Bg_i.
//
// The Jacobians are w.r.t. the increments Ceres applies: for a pose [p, q] the
// PoseLocalParameterization increment (p + dp, q (x) [1, dtheta/2] normalized), reported as a
// 15x7 block whose columns 0..5 are [dp, dtheta] and column 6 (q.w) is zero; for the
// speed-bias block [v, ba, bg] the additive increment (15x9). Upstream's blocks, where
// Qleft(q) and Qright(q) are the 4x4 left and right quaternion product matrices and br(.) their
// lower-right 3x3:
//   pose_i:  (p,p) = -R_i^T, (p,theta) = [Q_i^-1 (G T^2/2 + P_j - P_i - V_i T)]x,
//            (theta,theta) = -br(Qleft(Q_j^-1 Q_i) Qright(c_q)), (v,theta) = [Q_i^-1 (G T + V_j -
//            V_i)]x
//   sb_i:    (p,v) = -R_i^T T, (p,ba) = -J_p,ba, (p,bg) = -J_p,bg,
//            (theta,bg) = -br(Qleft(Q_j^-1 Q_i delta_q)) J_theta,bg   -- the UNcorrected delta_q
//            (v,v) = -R_i^T, (v,ba) = -J_v,ba, (v,bg) = -J_v,bg, (ba,ba) = -I, (bg,bg) = -I
//   pose_j:  (p,p) = R_i^T, (theta,theta) = br(Qleft(c_q^-1 Q_i^-1 Q_j))
//   sb_j:    (v,v) = R_i^T, (ba,ba) = I, (bg,bg) = I.
// At Bg_i = linearized_bg (c_q = delta_q, a unit quaternion) these are the derivatives of the
// residual. Away from it two upstream approximations stay, and are kept here: (theta,bg) uses
// delta_q where the derivative has c_q (an error of order |J_theta,bg dbg|: 2e-3 to 1.3e-2 on
// the reference cases, by central differences), and pose_i's (theta,theta) treats c_q as a unit
// quaternion: it is the derivative times |c_q|^2 = 1 + |J_theta,bg dbg|^2/4 (second order).
//
// Whitening: sqrt_info = LLT(covariance^-1).matrixL()^T, the upper factor U with U^T U =
// covariance^-1; the residual and each Jacobian are multiplied by it. The covariance's
// condition number reaches about 1e9 on the reference cases, so round-off in the covariance
// moves sqrt_info by up to about 1e-7 relative: those outputs are reproducible to that level
// only.
#pragma once

#include <Eigen/Geometry>

#include "imuconv/export.h"
#include "imuconv/kernels/vins_fusion.h"
#include "imuconv/status.h"
#include "imuconv/types.h"

namespace imuconv::kernels {

/// One of the factor's two parameter sets: pose [P, Q] and speed-bias [V, Ba, Bg].
/// Q is the body-to-world Hamilton quaternion as Ceres holds it (unit up to round-off).
struct VinsFusionFactorState {
  Vec3 P = Vec3::Zero();
  Eigen::Quaterniond Q = Eigen::Quaterniond::Identity();
  Vec3 V = Vec3::Zero(), Ba = Vec3::Zero(), Bg = Vec3::Zero();
};

/// An IntegrationBase after its last push_back: the preintegration, its linearization biases
/// and VINS's G (minus the gravity vector).
struct VinsFusionMeasurement {
  VinsFusionPreintegration pre;
  Vec3 linearized_ba = Vec3::Zero(), linearized_bg = Vec3::Zero();
  Vec3 G = Vec3(0.0, 0.0, 9.81);
};

/// The first-order bias correction evaluate() applies (header): delta_q corrected by deltaQ,
/// not normalized.
struct VinsFusionCorrectedDelta {
  Vec3 delta_p = Vec3::Zero();
  Eigen::Quaterniond delta_q = Eigen::Quaterniond::Identity();
  Vec3 delta_v = Vec3::Zero();
};

using Mat15x7 = Eigen::Matrix<double, 15, 7>;
using Mat15x9 = Eigen::Matrix<double, 15, 9>;

/// IMUFactor::Evaluate's outputs for one sqrt_info: the residual and the four Jacobian blocks.
struct VinsFusionFactorOutput {
  Vec15 residual = Vec15::Zero();
  Mat15x7 jacobian_pose_i = Mat15x7::Zero(), jacobian_pose_j = Mat15x7::Zero();
  Mat15x9 jacobian_speedbias_i = Mat15x9::Zero(), jacobian_speedbias_j = Mat15x9::Zero();
};

/// The correction at new start biases (ba, bg).
IMUCONV_API VinsFusionCorrectedDelta VinsFusionCorrect(const VinsFusionMeasurement& m,
                                                       const Vec3& ba, const Vec3& bg);

/// IntegrationBase::evaluate(): the 15-vector residual.
IMUCONV_API Vec15 VinsFusionEvaluate(const VinsFusionMeasurement& m, const VinsFusionFactorState& i,
                                     const VinsFusionFactorState& j);

/// IMUFactor::Evaluate with sqrt_info = I: the residual and the raw Jacobians.
IMUCONV_API VinsFusionFactorOutput VinsFusionRawFactor(const VinsFusionMeasurement& m,
                                                       const VinsFusionFactorState& i,
                                                       const VinsFusionFactorState& j);

/// sqrt_info = LLT(covariance^-1).matrixL()^T, as IMUFactor computes it. An error if the
/// inverse is not positive definite (upstream would go on with a meaningless factor).
IMUCONV_API Status VinsFusionSqrtInfo(const Mat15& covariance, Mat15& sqrt_info);

/// The raw outputs multiplied by sqrt_info: IMUFactor::Evaluate's own outputs.
IMUCONV_API VinsFusionFactorOutput VinsFusionWhiten(const VinsFusionFactorOutput& raw,
                                                    const Mat15& sqrt_info);

}  // namespace imuconv::kernels
