// `gtsam_pose3_vel`: the chart of the variables of GTSAM's ImuFactor / CombinedImuFactor,
// a gtsam::Pose3, a Vector3 velocity and a gtsam::imuBias::ConstantBias (accelerometer
// first), each perturbed by its own retract, Pose3's being the full Expmap (GTSAM built with
// GTSAM_POSE3_EXPMAP and GTSAM_ROT3_EXPMAP, its default options; without them Pose3
// retracts differently beyond first order and only the Jacobians below still agree):
//   R = R^ Exp(theta),  p = p^ + R^ Jl(theta) t,  v = v^ + dv (world frame),
//   ba = ba^ + dba,  bg = bg^ + dbg,                      order [theta, t, v, ba, bg], where t,
//   Pose3's
// translation coordinate, is the block that perturbs p (labelled "p").
// Jl is SO(3)'s left Jacobian, which is the V matrix of Pose3::Expmap(theta, t) =
// (Exp(theta), V(theta) t). local inverts it: theta = Log(R^T R_y),
// t = Jl^{-1}(theta) R^T (p_y - p^).
//
// Differs from `gtsam_navstate` only in the velocity (world frame here, body frame there)
// and, beyond first order, in the Jl(theta) coupling of the translation.
//
// Against `left`: dtheta_l = R^ theta exactly; dp_l = R^ Jl(theta) t, whose derivative at
// 0 is R^ (Jl(0) = I and the theta-derivative multiplies t = 0); dv_l = dv.
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

namespace {

using namespace imuconv::plugin::prelude;

// t is the p block.
constexpr BlockOrder kOrder{Block::theta, Block::p, Block::v, Block::ba, Block::bg};
constexpr std::array kBodyFrame{Block::theta,
                                Block::p};  // left's blocks rotated by R^T (to first order)

class GtsamPose3Vel
    : public imuconv::plugin::RotatedBlocksChart<imuconv::plugin::StateChart<kOrder>, kBodyFrame> {
 public:
  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    const Vec3 th = d.segment<3>(theta);
    y.R = x.R * so3::Exp(th);
    y.p = x.p + x.R * (so3::Jl(th) * d.segment<3>(p));
    y.v = x.v + d.segment<3>(v);
    RetractBiases(x, d, y);
  }

  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    const Mat3 Rt = x.R.transpose();
    const Vec3 th = so3::Log(Rt * y.R);
    d.segment<3>(theta) = th;
    d.segment<3>(p) = so3::JlInv(th) * (Rt * (y.p - x.p));
    d.segment<3>(v) = y.v - x.v;
    LocalBiases(x, y, d);
  }
};

}  // namespace

IMUCONV_PLUGIN(
    StateConvention, GtsamPose3Vel, "gtsam_pose3_vel", "1.0.0",
    "GTSAM ImuFactor variables: Pose3 Expmap, world-frame v + dv, b + db; [theta,t,v,ba,bg]")
