// Value types shared by every part of imuconv. Plain structs over fixed-size Eigen.
#pragma once

#include <Eigen/Core>
#include <cstddef>

namespace imuconv {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;
using Vec15 = Eigen::Matrix<double, 15, 1>;
using Mat15 = Eigen::Matrix<double, 15, 15>;
using Mat96 = Eigen::Matrix<double, 9, 6>;

/// One IMU sample: time in seconds, angular rate in rad/s and specific force in m/s^2,
/// both as measured in the body (IMU) frame, biases not removed.
struct ImuSample {
  double t = 0.0;
  Vec3 gyro = Vec3::Zero();
  Vec3 accel = Vec3::Zero();
};

/// Continuous-time IMU noise densities (the paper's q): white measurement noise and
/// bias random walks. Discretised as sigma^2/dt for measurement noise and sigma^2*dt for
/// the random walks (paper, section 2.1).
struct ImuNoise {
  double gyro_noise_density = 0.0;   ///< rad/s/sqrt(Hz)
  double accel_noise_density = 0.0;  ///< m/s^2/sqrt(Hz)
  double gyro_random_walk = 0.0;     ///< rad/s^2/sqrt(Hz)
  double accel_random_walk = 0.0;    ///< m/s^3/sqrt(Hz)
};

/// The 15-dof IMU state: body-to-world rotation R = R_ws, position and velocity of the
/// body in the world, gyro and accelerometer biases.
struct ImuState {
  Mat3 R = Mat3::Identity();
  Vec3 p = Vec3::Zero();
  Vec3 v = Vec3::Zero();
  Vec3 bg = Vec3::Zero();
  Vec3 ba = Vec3::Zero();
};

/// The preintegrated increment (paper, eq. preint-theta..preint-b): rotation, position
/// and velocity increments in the start body frame and the accumulated bias random walk
/// Delta b = [Delta b_g, Delta b_a] (zero as an estimate; perturbed by conventions).
struct PreintIncrement {
  Mat3 dR = Mat3::Identity();
  Vec3 dp = Vec3::Zero();
  Vec3 dv = Vec3::Zero();
  Vec3 dbg = Vec3::Zero();
  Vec3 dba = Vec3::Zero();
};

}  // namespace imuconv
