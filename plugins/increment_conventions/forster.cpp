// `forster`: the preintegrated-measurement perturbation of Forster et al., IEEE TRO 2017,
// the paper's f perturbation (eq. preint-error-forster): the measurement is the estimate
// minus a noise, so every block enters with a minus sign,
//   Delta R = Delta R^ Exp(-dtheta),  dp = dp^ - dp,  dv = dv^ - dv,  Delta b = Delta b^ - db,
// order [theta, p, v, bg, ba]. With this sign Forster's residual Jacobian is close to the
// identity (eq. forster-res-jac), so its measurement covariance is nearly the residual's.
//
// Against `preint_reference` (same order, plus signs): exactly -I both ways, since
// Exp(-dtheta) = Exp(dtheta_r) with dtheta_r = -dtheta.
#include "imuconv/plugin_abi.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace {

using imuconv::Mat15;
using imuconv::PreintIncrement;
using imuconv::Vec15;
namespace so3 = imuconv::so3;

namespace idx {
constexpr int theta = 0, p = 3, v = 6, bg = 9, ba = 12;
}

// -I, written as a fill (Eigen's -Mat15::Identity() expression is several times slower).
void MinusIdentity(Mat15& J) {
  J.setZero();
  J.diagonal().setConstant(-1.0);
}

class ForsterIncrement final : public imuconv::PreintConvention {
 public:
  const char* id() const noexcept override { return "forster"; }
  imuconv::BlockLabels labels() const noexcept override { return {"theta", "p", "v", "bg", "ba"}; }

  void retract(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) const noexcept override {
    y.dR = x.dR * so3::Exp(-d.segment<3>(idx::theta));
    y.dp = x.dp - d.segment<3>(idx::p);
    y.dv = x.dv - d.segment<3>(idx::v);
    y.dbg = x.dbg - d.segment<3>(idx::bg);
    y.dba = x.dba - d.segment<3>(idx::ba);
  }

  void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept override {
    d.segment<3>(idx::theta) = -so3::Log(x.dR.transpose() * y.dR);
    d.segment<3>(idx::p) = x.dp - y.dp;
    d.segment<3>(idx::v) = x.dv - y.dv;
    d.segment<3>(idx::bg) = x.dbg - y.dbg;
    d.segment<3>(idx::ba) = x.dba - y.dba;
  }

  bool jacobian_to_reference(const PreintIncrement&, Mat15& J) const noexcept override {
    MinusIdentity(J);
    return true;
  }

  bool jacobian_from_reference(const PreintIncrement&, Mat15& J) const noexcept override {
    MinusIdentity(J);
    return true;
  }
};

}  // namespace

IMUCONV_PLUGIN(PreintConvention, ForsterIncrement, "forster", "1.0.0",
               "Forster et al. TRO 2017 (paper's f): dR Exp(-dtheta), dp - dp, dv - dv, Db - db; [theta,p,v,bg,ba]")
