// A state as a system's own state struct, for the kernels that take one with the same five
// quantities under the system's names (OKVIS's Okvis2State, VINS-Fusion's IMUFactor state,
// IKFoM's state_ikfom): the same position, rotation as a quaternion, velocity and biases.
#pragma once

#include <Eigen/Geometry>

#include "imuconv/types.h"

namespace imuconv::kernels {

/// `x` in S, each quantity in the member of S named for it; S's other members keep their
/// defaults. The quaternion is Eigen's of x.R (its sign as Eigen chooses it).
template <class S>
S SystemStateOf(const ImuState& x, Vec3 S::*p, Eigen::Quaterniond S::*q, Vec3 S::*v, Vec3 S::*bg,
                Vec3 S::*ba) {
  S s;
  s.*p = x.p;
  s.*q = Eigen::Quaterniond(x.R);
  s.*v = x.v;
  s.*bg = x.bg;
  s.*ba = x.ba;
  return s;
}

}  // namespace imuconv::kernels
