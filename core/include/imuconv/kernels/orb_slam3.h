// ORB-SLAM3's IMU preintegration (UZ-SLAMLab/ORB_SLAM3: IMU::Preintegrated, the tracking
// prediction and EdgeInertial), reproduced in single precision as the original computes it,
// with its feeding, noise interpretation and error states.
//
// The step (float; acc = a - ba, w = g - bg; a, g the mean of two consecutive samples, dt
// the float of their time difference):
//   dP += dV dt + dR acc dt^2/2,  dV += dR acc dt,  dR <- Normalize(dR Exp(w dt))  (SVD)
//   C[0:9] <- A C[0:9] A^T + B Nga B^T,  C[9:15] += NgaWalk   (order [theta, v, p, bg, ba])
// with A = [[DR^T, 0, 0], [-dR [acc]x dt, I, 0], [-dR [acc]x dt^2/2, I dt, I]],
// B = [[Jr dt, 0], [0, dR dt], [0, dR dt^2/2]], DR = Exp(w dt), Jr its right Jacobian (first
// order, Jr = I and DR = I + [w dt]x, below |w dt| = 1e-4). The state-bias cross blocks are
// never formed, and the bias random walk is added once per step whatever dt is.
// In exact arithmetic this is the OpenVINS `discrete` scheme; in float, dT, the sum of the
// steps' float dt, drifts (2000 steps of 5 ms: 10.000181 s), and the edge uses that dT.
//
// Noise, as ORB-SLAM3's Tracking builds IMU::Calib from its yaml (IMU.NoiseGyro, NoiseAcc,
// GyroWalk, AccWalk: continuous densities; IMU.Frequency f): Nga = diag(Ng^2 f, Na^2 f)
// (per-sample variances), NgaWalk = diag(Ngw^2 / f, Naw^2 / f) (per-step variances).
//
// Error states: the preintegration's dR = dR^ Exp(dtheta) (right, frame of the first
// sample), dV, dP additive, biases additive; the bias Jacobians are d delta / d bias
// (dR(b) = dR Exp(JRg dbg)). EdgeInertial's residual [Log(dR(b)^T R1^T R2), R1^T(v2 - v1 -
// g dT) - dV(b), R1^T(p2 - p1 - v1 dT - g dT^2/2) - dP(b)] (double, from the float deltas),
// its pose increments ImuCamPose::Update's: R <- R Exp(dtheta), t <- t + R dt.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "imuconv/export.h"
#include "imuconv/status.h"
#include "imuconv/types.h"

namespace imuconv::kernels {

using Mat3f = Eigen::Matrix3f;
using Vec3f = Eigen::Vector3f;

/// IMU::Calib's noise: Nga = diag(gyro x3, accel x3) per-sample variances, NgaWalk likewise
/// per step.
struct OrbSlam3Calib {
  Eigen::Matrix<float, 6, 1> cov = Eigen::Matrix<float, 6, 1>::Zero();
  Eigen::Matrix<float, 6, 1> cov_walk = Eigen::Matrix<float, 6, 1>::Zero();
};

/// The Calib that ORB-SLAM3's Tracking makes from the yaml's densities and IMU rate f:
/// IMU::Calib(Ng sqrt f, Na sqrt f, Ngw / sqrt f, Naw / sqrt f), squared, all in float.
IMUCONV_API OrbSlam3Calib OrbSlam3CalibFromDensities(const ImuNoise& densities,
                                                     double frequency_hz);

/// IMU::Bias, in float.
struct OrbSlam3Bias {
  Vec3f bg = Vec3f::Zero();
  Vec3f ba = Vec3f::Zero();
};

/// One integrated step as IMU::Preintegrated keeps it (for Reintegrate).
struct OrbSlam3Step {
  Vec3f accel = Vec3f::Zero();
  Vec3f gyro = Vec3f::Zero();
  float dt = 0.0f;
};

/// IMU::Preintegrated after the last IntegrateNewMeasurement.
struct OrbSlam3Preintegrated {
  OrbSlam3Bias b;  ///< the bias it was integrated at
  float dT = 0.0f;
  Mat3f dR = Mat3f::Identity();
  Vec3f dV = Vec3f::Zero(), dP = Vec3f::Zero();
  Mat3f JRg = Mat3f::Zero(), JVg = Mat3f::Zero(), JVa = Mat3f::Zero(), JPg = Mat3f::Zero(),
        JPa = Mat3f::Zero();
  Vec3f avgA = Vec3f::Zero(), avgW = Vec3f::Zero();
  Eigen::Matrix<float, 15, 15> C = Eigen::Matrix<float, 15, 15>::Zero();
  std::vector<OrbSlam3Step> steps;
};

/// The steps of Tracking::PreintegrateIMU between two frames at the first and last sample:
/// the mean of consecutive samples (stored in float), dt the float of their double time
/// difference.
IMUCONV_API Status OrbSlam3Steps(const std::vector<ImuSample>& samples,
                                 std::vector<OrbSlam3Step>& steps);

/// IMU::Preintegrated(b, calib) fed `steps` by IntegrateNewMeasurement. Reintegrate at a new
/// bias is this call with the same steps and that bias.
IMUCONV_API OrbSlam3Preintegrated PreintegrateOrbSlam3(const std::vector<OrbSlam3Step>& steps,
                                                       const OrbSlam3Calib& calib,
                                                       const OrbSlam3Bias& b);

/// GetDeltaRotation / GetDeltaVelocity / GetDeltaPosition at the bias `b`: the first-order
/// bias update (GetUpdatedDelta* after SetNewBias(b) gives the same).
IMUCONV_API Mat3f OrbSlam3DeltaRotation(const OrbSlam3Preintegrated& pre, const OrbSlam3Bias& b);
IMUCONV_API Vec3f OrbSlam3DeltaVelocity(const OrbSlam3Preintegrated& pre, const OrbSlam3Bias& b);
IMUCONV_API Vec3f OrbSlam3DeltaPosition(const OrbSlam3Preintegrated& pre, const OrbSlam3Bias& b);

/// A body state in world: R body to world, p, v.
template <typename Scalar>
struct OrbSlam3Pose {
  Eigen::Matrix<Scalar, 3, 3> R = Eigen::Matrix<Scalar, 3, 3>::Identity();
  Eigen::Matrix<Scalar, 3, 1> p = Eigen::Matrix<Scalar, 3, 1>::Zero();
  Eigen::Matrix<Scalar, 3, 1> v = Eigen::Matrix<Scalar, 3, 1>::Zero();
};

/// Tracking::PredictStateIMU, in float, from the start state at the integration's bias,
/// with gravity (0, 0, -9.81f).
IMUCONV_API OrbSlam3Pose<float> PredictOrbSlam3Tracking(const OrbSlam3Preintegrated& pre,
                                                        const OrbSlam3Pose<float>& start);

/// The same relation in double (what EdgeInertial's residual encodes): the float deltas and
/// dT cast to double, g = (0, 0, -(double)9.81f), R normalized by SVD.
IMUCONV_API OrbSlam3Pose<double> PredictOrbSlam3(const OrbSlam3Preintegrated& pre,
                                                 const OrbSlam3Pose<double>& start);

/// EdgeInertial between (state 1, biases b1) and state 2.
struct OrbSlam3EdgeInertial {
  Mat9 information = Mat9::Zero();  ///< order [er, ev, ep]
  Vec9 residual = Vec9::Zero();
  double chi2 = 0.0;
  Eigen::Matrix<double, 9, 6> J_pose1 = Eigen::Matrix<double, 9, 6>::Zero();  ///< [dtheta, dt]
  Eigen::Matrix<double, 9, 3> J_vel1 = Eigen::Matrix<double, 9, 3>::Zero();
  Eigen::Matrix<double, 9, 3> J_gyro_bias1 = Eigen::Matrix<double, 9, 3>::Zero();
  Eigen::Matrix<double, 9, 3> J_acc_bias1 = Eigen::Matrix<double, 9, 3>::Zero();
  Eigen::Matrix<double, 9, 6> J_pose2 = Eigen::Matrix<double, 9, 6>::Zero();
  Eigen::Matrix<double, 9, 3> J_vel2 = Eigen::Matrix<double, 9, 3>::Zero();
};

/// EdgeInertial's information (its constructor: C[0:9] inverted in double, symmetrized,
/// eigenvalues below 1e-12 set to 0).
IMUCONV_API Mat9 OrbSlam3EdgeInformation(const OrbSlam3Preintegrated& pre);

/// EdgeInertial's computeError and linearizeOplus. The biases b1 (double vertices) are read
/// into IMU::Bias, in float, as upstream does.
IMUCONV_API OrbSlam3EdgeInertial EvaluateOrbSlam3EdgeInertial(const OrbSlam3Preintegrated& pre,
                                                              const OrbSlam3Pose<double>& state1,
                                                              const Vec3& bg1, const Vec3& ba1,
                                                              const OrbSlam3Pose<double>& state2);

}  // namespace imuconv::kernels
