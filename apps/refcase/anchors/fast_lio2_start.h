// The FAST-LIO2 anchors' start covariance (tests/data/reference/anchors/README.md, fast-lio2/):
// the case's cov_s_left in IKFoM's 23-dimensional error state (kernels/fast_lio2.h). The
// writer (fast_lio2.cpp) starts its runs from it and tests/reference/fast_lio2_anchor.cpp holds
// the file's P0 to it, so the recipe is stated once.
#pragma once

#include <Eigen/Geometry>

#include "imuconv/kernels/fast_lio2.h"

namespace imuconv::refcase {

/// P0 = T cov_s_left T^T: cov_s_left's [dp, dtheta, dv, dbg, dba] (R = Exp(dtheta) R^) in the
/// error state, drot = R^T dtheta with R the start rotation `rot`, zero in the extrinsic and
/// gravity blocks.
inline kernels::Mat23 FastLio2StartCovariance(const Eigen::Quaterniond& rot,
                                              const Mat15& cov_left) {
  using namespace kernels;
  Eigen::Matrix<double, 23, 15> T = Eigen::Matrix<double, 23, 15>::Zero();
  T.block<3, 3>(kFastLio2Pos, 0).setIdentity();
  T.block<3, 3>(kFastLio2Rot, 3) = rot.toRotationMatrix().transpose();
  T.block<3, 3>(kFastLio2Vel, 6).setIdentity();
  T.block<3, 3>(kFastLio2Bg, 9).setIdentity();
  T.block<3, 3>(kFastLio2Ba, 12).setIdentity();
  return T * cov_left * T.transpose();
}

}  // namespace imuconv::refcase
