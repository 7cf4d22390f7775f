// `gtsam_tangent`: the chart of GTSAM's TangentPreintegration, whose state is the tangent
// 9-vector preintegrated_ = [theta, p, v] with Delta R = Exp(theta), perturbed additively in
// that vector space; its bias entry has the paper's sign, Delta b = Delta b^ - db
// (eq. subeq:preint-error-db), and GTSAM's order (accelerometer first):
//   Delta R = Exp(Log(Delta R^) + dtheta),  dp = dp^ + dp,  dv = dv^ + dv,
//   Delta b_a = Delta b_a^ - dba,  Delta b_g = Delta b_g^ - dbg,
// order [theta, p, v, ba, bg]. local: dtheta = Log(Delta R_y) - Log(Delta R^), the others
// differences. The increment is stored as a rotation matrix, so its tangent coordinate is
// Log(Delta R) in (-pi, pi]: the chart is valid only while |Log(Delta R^) + dtheta| < pi,
// which any realistic preintegration interval satisfies (GTSAM's own representation has
// the same limit).
//
// Against `preint_reference` (Delta R = Delta R^ Exp(dtheta_r)): with psi = Log(Delta R^),
// Exp(psi + dtheta) = Exp(psi) Exp(Jr(psi) dtheta + O(|dtheta|^2)), so dtheta_r = Jr(psi)
// dtheta to first order and dtheta = Jr^{-1}(psi) dtheta_r; translations pass through,
// bias blocks are -I (sign) with ba and bg swapped (order).
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

namespace {

using namespace imuconv::plugin::prelude;

// GTSAM's order, accelerometer bias first.
constexpr BlockOrder kOrder{Block::theta, Block::p, Block::v, Block::ba, Block::bg};

class GtsamTangent : public imuconv::plugin::IncrementChart<kOrder, -1> {
 public:
  void retract(const PreintIncrement& x, const Vec15& d,
               PreintIncrement& y) const noexcept override {
    y.dR = so3::Exp(so3::Log(x.dR) + d.segment<3>(theta));
    y.dp = x.dp + d.segment<3>(p);
    y.dv = x.dv + d.segment<3>(v);
    RetractBiases(x, d, y);
  }

  void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept override {
    d.segment<3>(theta) = so3::Log(y.dR) - so3::Log(x.dR);
    d.segment<3>(p) = y.dp - x.dp;
    d.segment<3>(v) = y.dv - x.dv;
    LocalBiases(x, y, d);
  }

  bool J_ref_this(const PreintIncrement& x, Mat15& J) const noexcept override {
    return RefThis(J, {{Block::theta, so3::Jr(so3::Log(x.dR))}});
  }
  bool J_this_ref(const PreintIncrement& x, Mat15& J) const noexcept override {
    return ThisRef(J, {{Block::theta, so3::JrInv(so3::Log(x.dR))}});
  }
};

}  // namespace

IMUCONV_PLUGIN(IncrementConvention, GtsamTangent, "gtsam_tangent", "1.0.0",
               "GTSAM TangentPreintegration: Exp(Log dR + dtheta), dp + dp, dv + dv, Db - db; "
               "[theta,p,v,ba,bg]")
