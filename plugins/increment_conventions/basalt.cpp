// `basalt`: the delta-state perturbation of Basalt's IntegratedImuMeasurement (its 9x9
// covariance and d_state_d_ba, d_state_d_bg; PoseVelState::applyInc), order [p, theta, v]
// ([trans, rot, vel]) followed by the biases in Basalt's state order [bg, ba]:
//   dp = dp^ + dp,  Delta R = Exp(dtheta) Delta R^ (LEFT, in the start frame),  dv = dv^ + dv,
//   Delta b = Delta b^ + db.
// Basalt's delta state has no bias entry; here it is the random walk over the interval that
// Basalt's separate bias factors weight, with the plus sign of a state's bias error.
//
// Against `preint_reference` (right rotation error): Exp(dtheta) dR^ = dR^ Exp(dR^T dtheta),
// so dtheta_ref = dR^T dtheta and dtheta = dR^ dtheta_ref; the other blocks are a
// permutation.
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

namespace {

using namespace imuconv::plugin::prelude;

constexpr BlockOrder kOrder{Block::p, Block::theta, Block::v, Block::bg, Block::ba};

class BasaltIncrement : public imuconv::plugin::IncrementChart<kOrder, 1> {
 public:
  void retract(const PreintIncrement& x, const Vec15& d,
               PreintIncrement& y) const noexcept override {
    y.dR = so3::Exp(d.segment<3>(theta)) * x.dR;
    y.dp = x.dp + d.segment<3>(p);
    y.dv = x.dv + d.segment<3>(v);
    RetractBiases(x, d, y);
  }

  void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept override {
    d.segment<3>(theta) = so3::Log(y.dR * x.dR.transpose());
    d.segment<3>(p) = y.dp - x.dp;
    d.segment<3>(v) = y.dv - x.dv;
    LocalBiases(x, y, d);
  }

  bool J_ref_this(const PreintIncrement& x, Mat15& J) const noexcept override {
    return RefThis(J, {{Block::theta, x.dR.transpose()}});
  }
  bool J_this_ref(const PreintIncrement& x, Mat15& J) const noexcept override {
    return ThisRef(J, {{Block::theta, x.dR}});
  }
};

}  // namespace

IMUCONV_PLUGIN(IncrementConvention, BasaltIncrement, "basalt", "1.0.0",
               "Basalt IntegratedImuMeasurement delta state: dp + dp, Exp(dtheta) dR, dv + dv, Db "
               "+ db; [p,theta,v,bg,ba]")
