// `forster`: the preintegrated-measurement perturbation of Forster et al., IEEE TRO 2017,
// the paper's f perturbation (eq. preint-error-forster): the measurement is the estimate
// minus a noise, so every block enters with a minus sign,
//   Delta R = Delta R^ Exp(-dtheta),  dp = dp^ - dp,  dv = dv^ - dv,  Delta b = Delta b^ - db,
// order [theta, p, v, bg, ba]. With this sign Forster's residual Jacobian is close to the
// identity (eq. forster-res-jac), so its measurement covariance is nearly the residual's.
//
// Against `preint_reference` (same order, plus signs): exactly -I both ways, since
// Exp(-dtheta) = Exp(dtheta_r) with dtheta_r = -dtheta.
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

namespace {

using namespace imuconv::plugin::prelude;

// -I, written as a fill (Eigen's -Mat15::Identity() expression is several times slower).
bool MinusIdentity(Mat15& J) {
  J.setZero();
  J.diagonal().setConstant(-1.0);
  return true;
}

class ForsterIncrement
    : public imuconv::plugin::IncrementChart<imuconv::kPreintReferenceOrder, -1> {
 public:
  void retract(const PreintIncrement& x, const Vec15& d,
               PreintIncrement& y) const noexcept override {
    y.dR = x.dR * so3::Exp(-d.segment<3>(theta));
    y.dp = x.dp - d.segment<3>(p);
    y.dv = x.dv - d.segment<3>(v);
    RetractBiases(x, d, y);
  }

  void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept override {
    d.segment<3>(theta) = -so3::Log(x.dR.transpose() * y.dR);
    d.segment<3>(p) = x.dp - y.dp;
    d.segment<3>(v) = x.dv - y.dv;
    LocalBiases(x, y, d);
  }

  bool J_ref_this(const PreintIncrement&, Mat15& J) const noexcept override {
    return MinusIdentity(J);
  }
  bool J_this_ref(const PreintIncrement&, Mat15& J) const noexcept override {
    return MinusIdentity(J);
  }
};

}  // namespace

IMUCONV_PLUGIN(IncrementConvention, ForsterIncrement, "forster", "1.0.0",
               "Forster et al. TRO 2017 (paper's f): dR Exp(-dtheta), dp - dp, dv - dv, Db - db; "
               "[theta,p,v,bg,ba]")
