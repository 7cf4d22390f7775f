// `gtsam_pose3_vel`: the chart of the variables of GTSAM's ImuFactor / CombinedImuFactor,
// a gtsam::Pose3, a Vector3 velocity and a gtsam::imuBias::ConstantBias (accelerometer
// first), each perturbed by its own retract, Pose3's being the full Expmap (GTSAM built with
// GTSAM_POSE3_EXPMAP and GTSAM_ROT3_EXPMAP, its default options; without them Pose3
// retracts differently beyond first order and only the Jacobians below still agree):
//   R = R^ Exp(theta),  p = p^ + R^ Jl(theta) t,  v = v^ + dv (world frame),
//   ba = ba^ + dba,  bg = bg^ + dbg,                      order [theta, t, v, ba, bg].
// Jl is SO(3)'s left Jacobian, which is the V matrix of Pose3::Expmap(theta, t) =
// (Exp(theta), V(theta) t). local inverts it: theta = Log(R^T R_y),
// t = Jl^{-1}(theta) R^T (p_y - p^).
//
// Differs from `gtsam_navstate` only in the velocity (world frame here, body frame there)
// and, beyond first order, in the Jl(theta) coupling of the translation.
//
// Against `left`: dtheta_l = R^ theta exactly; dp_l = R^ Jl(theta) t, whose derivative at
// 0 is R^ (Jl(0) = I and the theta-derivative multiplies t = 0); dv_l = dv.
#include "imuconv/plugin_abi.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace {

using imuconv::ImuState;
using imuconv::Mat15;
using imuconv::Mat3;
using imuconv::Vec15;
using imuconv::Vec3;
namespace so3 = imuconv::so3;
namespace ref = imuconv::left_idx;

namespace idx {
constexpr int theta = 0, t = 3, v = 6, ba = 9, bg = 12;
}

class GtsamPose3Vel final : public imuconv::ErrorState {
 public:
  const char* id() const noexcept override { return "gtsam_pose3_vel"; }
  imuconv::BlockLabels labels() const noexcept override { return {"theta", "p", "v", "ba", "bg"}; }

  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    const Vec3 theta = d.segment<3>(idx::theta);
    y.R = x.R * so3::Exp(theta);
    y.p = x.p + x.R * (so3::Jl(theta) * d.segment<3>(idx::t));
    y.v = x.v + d.segment<3>(idx::v);
    y.ba = x.ba + d.segment<3>(idx::ba);
    y.bg = x.bg + d.segment<3>(idx::bg);
  }

  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    const Mat3 Rt = x.R.transpose();
    const Vec3 theta = so3::Log(Rt * y.R);
    d.segment<3>(idx::theta) = theta;
    d.segment<3>(idx::t) = so3::JlInv(theta) * (Rt * (y.p - x.p));
    d.segment<3>(idx::v) = y.v - x.v;
    d.segment<3>(idx::ba) = y.ba - x.ba;
    d.segment<3>(idx::bg) = y.bg - x.bg;
  }

  bool jacobian_to_reference(const ImuState& x, Mat15& J) const noexcept override {
    J.setZero();
    J.block<3, 3>(ref::theta, idx::theta) = x.R;
    J.block<3, 3>(ref::p, idx::t) = x.R;
    J.block<3, 3>(ref::v, idx::v).setIdentity();
    J.block<3, 3>(ref::ba, idx::ba).setIdentity();
    J.block<3, 3>(ref::bg, idx::bg).setIdentity();
    return true;
  }

  bool jacobian_from_reference(const ImuState& x, Mat15& J) const noexcept override {
    const Mat3 Rt = x.R.transpose();
    J.setZero();
    J.block<3, 3>(idx::theta, ref::theta) = Rt;
    J.block<3, 3>(idx::t, ref::p) = Rt;
    J.block<3, 3>(idx::v, ref::v).setIdentity();
    J.block<3, 3>(idx::ba, ref::ba).setIdentity();
    J.block<3, 3>(idx::bg, ref::bg).setIdentity();
    return true;
  }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, GtsamPose3Vel, "gtsam_pose3_vel", "1.0.0",
               "GTSAM ImuFactor variables: Pose3 Expmap, world-frame v + dv, b + db; [theta,t,v,ba,bg]")
