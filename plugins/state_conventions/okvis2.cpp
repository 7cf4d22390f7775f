// `okvis2`: the error state of OKVIS2's ImuError::propagation (its covariance and Jacobian,
// okvis_ceres ImuError.cpp) and of its estimator's pose and speed-and-bias blocks
// (PoseManifold::plus, PoseLocalParameterization.cpp), order [r, alpha, v, bg, ba]:
//   r = r^ + dr (world),  C_WS = Exp(dalpha) C_WS^ (LEFT, world frame; upstream forms it as
//   the quaternion product deltaQ(dalpha) (x) q_WS^, the same rotation),
//   v = v^ + dv (world),  b = b^ + db.
//
// Against `left` (p + dp, Exp(dtheta) R, v + dv, b + db, order [p, theta, v, bg, ba]): the
// same perturbation of every block in the same order, so both Jacobians are the identity
// (derived block by block: dr = dp, dalpha = dtheta, dv = dv, db = db). The chart is `left`
// under OKVIS's name, so that an OKVIS covariance can be declared as what it is.
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

namespace {

using imuconv::ImuState;
using imuconv::Mat15;
using imuconv::Vec15;

// OKVIS's [r, alpha, v, bg, ba]: imuconv's names p and theta for r and alpha.
constexpr imuconv::BlockOrder kOkvisOrder{imuconv::Block::p, imuconv::Block::theta,
                                          imuconv::Block::v, imuconv::Block::bg,
                                          imuconv::Block::ba};

class Okvis2State : public imuconv::plugin::StateChart<kOkvisOrder> {
 public:
  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    y.p = x.p + d.segment<3>(p);
    y.R = imuconv::so3::Exp(d.segment<3>(theta)) * x.R;
    y.v = x.v + d.segment<3>(v);
    RetractBiases(x, d, y);
  }
  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    d.segment<3>(p) = y.p - x.p;
    d.segment<3>(theta) = imuconv::so3::Log(y.R * x.R.transpose());
    d.segment<3>(v) = y.v - x.v;
    LocalBiases(x, y, d);
  }
  bool J_ref_this(const ImuState&, Mat15& J) const noexcept override { return RefThis(J, {}); }
  bool J_this_ref(const ImuState&, Mat15& J) const noexcept override { return ThisRef(J, {}); }
};

}  // namespace

IMUCONV_PLUGIN(
    StateConvention, Okvis2State, "okvis2", "1.0.0",
    "OKVIS2 ImuError/PoseManifold error state: r+dr, Exp(dalpha)C_WS, v+dv, b+db (world); "
    "[r,alpha,v,bg,ba] = left")
