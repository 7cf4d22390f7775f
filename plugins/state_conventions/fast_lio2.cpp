// `fast_lio2`: the error state of FAST-LIO2 (hku-mars/FAST_LIO, use-ikfom.hpp's state_ikfom
// on IKFoM's manifold toolkit, MTK), restricted to imuconv's 15 dimensions. IKFoM's boxplus
// moves each component of the state by its own manifold's operation:
//   pos = pos^ + dpos (world),  rot = rot^ Exp(drot) (right, body: MTK SO3::boxplus),
//   vel = vel^ + dvel (world),  bg = bg^ + dbg,  ba = ba^ + dba,
// order [pos, rot, vel, bg, ba] as in state_ikfom. That 23-dimensional state also holds the
// lidar-IMU extrinsics (offset_R_L_I, offset_T_L_I: 6 dims) and the gravity on FAST-LIO's S2
// sphere (2 dims) between rot and vel; those 8 are outside imuconv's 15-dimensional states.
// Their numbers are in the kernel (core/include/imuconv/kernels/fast_lio2.h,
// PropagateFastLio2Scan: the 23x23 covariance, transition and noise) and in
// `imuconv refcase CASE.json --anchor fast-lio2` (docs/fast-lio2.md).
//
// Against `left` (p + dp, Exp(dtheta) R, v + dv, b + db): R^ Exp(drot) = Exp(R^ drot) R^, so
// dtheta_l = R^ drot exactly; dp, dv and the biases are the same.
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

namespace {

using namespace imuconv::plugin::prelude;

constexpr BlockOrder kOrder{Block::p, Block::theta, Block::v, Block::bg, Block::ba};
constexpr std::array kBodyFrame{Block::theta};  // left's rotation block rotated by R^T

class FastLio2
    : public imuconv::plugin::RotatedBlocksChart<imuconv::plugin::StateChart<kOrder>, kBodyFrame> {
 public:
  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    y.R = x.R * so3::Exp(d.segment<3>(theta));
    y.p = x.p + d.segment<3>(p);
    y.v = x.v + d.segment<3>(v);
    RetractBiases(x, d, y);
  }

  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    d.segment<3>(theta) = so3::Log(x.R.transpose() * y.R);
    d.segment<3>(p) = y.p - x.p;
    d.segment<3>(v) = y.v - x.v;
    LocalBiases(x, y, d);
  }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, FastLio2, "fast_lio2", "1.0.0",
               "FAST-LIO2 (IKFoM state_ikfom) without extrinsics and S2 gravity: pos + dp, "
               "R Exp(dtheta), vel + dv, b + db; [pos, rot, vel, bg, ba]")
