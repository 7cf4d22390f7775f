// `euler_angles`: the error state of a classic attitude EKF that keeps roll, pitch and yaw.
// R = Rz(yaw) Ry(pitch) Rx(roll) (ZYX, body to world); the rotation error is additive in the
// three angles, p and v are additive in the world frame, biases additive; block order
// [p, v, theta, ba, bg] (theta holds d(roll, pitch, yaw)). The chart is singular at pitch
// +-90 degrees, as such filters are: conversions there are not defined.
//
// No analytic Jacobians: the registry derives this convention's conversions from retract and
// local by Ridders' differences, and checks the chart when it loads the plugin.
#include <imuconv/plugin_abi.h>

#include <algorithm>
#include <cmath>

namespace {

using imuconv::Block;
using imuconv::ImuState;
using imuconv::Mat3;
using imuconv::Vec15;
using imuconv::Vec3;

Mat3 FromRollPitchYaw(const Vec3& rpy) {
  const double cr = std::cos(rpy[0]), sr = std::sin(rpy[0]);
  const double cp = std::cos(rpy[1]), sp = std::sin(rpy[1]);
  const double cy = std::cos(rpy[2]), sy = std::sin(rpy[2]);
  Mat3 R;
  R << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return R;
}

Vec3 RollPitchYaw(const Mat3& R) {
  return Vec3(std::atan2(R(2, 1), R(2, 2)), std::asin(std::clamp(-R(2, 0), -1.0, 1.0)),
              std::atan2(R(1, 0), R(0, 0)));
}

/// An angle difference in (-pi, pi]: roll and yaw wrap.
double Wrapped(double a) { return std::remainder(a, 2.0 * M_PI); }

class EulerAngles : public imuconv::StateConvention {
 public:
  imuconv::BlockOrder order() const noexcept override {
    return {Block::p, Block::v, Block::theta, Block::ba, Block::bg};
  }
  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    y.p = x.p + d.segment<3>(0);
    y.v = x.v + d.segment<3>(3);
    y.R = FromRollPitchYaw(RollPitchYaw(x.R) + d.segment<3>(6));
    y.ba = x.ba + d.segment<3>(9);
    y.bg = x.bg + d.segment<3>(12);
  }
  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    const Vec3 a = RollPitchYaw(x.R), b = RollPitchYaw(y.R);
    d.segment<3>(0) = y.p - x.p;
    d.segment<3>(3) = y.v - x.v;
    d.segment<3>(6) = Vec3(Wrapped(b[0] - a[0]), b[1] - a[1], Wrapped(b[2] - a[2]));
    d.segment<3>(9) = y.ba - x.ba;
    d.segment<3>(12) = y.bg - x.bg;
  }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, EulerAngles, "euler_angles", "1.0.0",
               "roll-pitch-yaw EKF error state: p+dp, v+dv (world), rpy+drpy (ZYX), b+db; [p, v, "
               "theta, ba, bg]")
