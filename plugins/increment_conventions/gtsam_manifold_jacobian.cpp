// `gtsam_manifold_jacobian`: the chart GTSAM's ManifoldPreintegration (and the tangent
// preintegration's Jacobians) state their bias Jacobians delRdelBiasOmega, delPdelBiasAcc,
// delPdelBiasOmega, delVdelBiasAcc, delVdelBiasOmega in, the paper's j perturbation
// (eq. subeq:preint-error-dr..subeq:preint-error-db): a right perturbation of the rotation
// and vector-space differences of dp and dv, as GTSAM's BiasCorrectionJacobians tests
// differentiate them, with the bias entry's sign Delta b = Delta b^ - db:
//   Delta R = Delta R^ Exp(dtheta),  dp = dp^ + dp,  dv = dv^ + dv,
//   Delta b_a = Delta b_a^ - dba,  Delta b_g = Delta b_g^ - dbg,
// order [theta, p, v, ba, bg].
//
// Against `preint_reference` it differs only in the bias sign and order: the Jacobians are
// identities on theta, p, v and -I on the swapped bias blocks.
#include "imuconv/plugin_abi.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace {

using imuconv::Mat15;
using imuconv::Mat3;
using imuconv::PreintIncrement;
using imuconv::Vec15;
namespace so3 = imuconv::so3;
namespace ref = imuconv::pref_idx;

namespace idx {
constexpr int theta = 0, p = 3, v = 6, ba = 9, bg = 12;
}

// The same permutation-with-sign both ways: it is its own inverse.
void SignedBiasSwap(Mat15& J) {
  J.setZero();
  J.block<3, 3>(idx::theta, ref::theta).setIdentity();
  J.block<3, 3>(idx::p, ref::p).setIdentity();
  J.block<3, 3>(idx::v, ref::v).setIdentity();
  J.block<3, 3>(idx::ba, ref::ba) = -Mat3::Identity();
  J.block<3, 3>(idx::bg, ref::bg) = -Mat3::Identity();
}

class GtsamManifoldJacobian final : public imuconv::PreintConvention {
 public:
  const char* id() const noexcept override { return "gtsam_manifold_jacobian"; }
  imuconv::BlockLabels labels() const noexcept override { return {"theta", "p", "v", "ba", "bg"}; }

  void retract(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) const noexcept override {
    y.dR = x.dR * so3::Exp(d.segment<3>(idx::theta));
    y.dp = x.dp + d.segment<3>(idx::p);
    y.dv = x.dv + d.segment<3>(idx::v);
    y.dba = x.dba - d.segment<3>(idx::ba);
    y.dbg = x.dbg - d.segment<3>(idx::bg);
  }

  void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept override {
    d.segment<3>(idx::theta) = so3::Log(x.dR.transpose() * y.dR);
    d.segment<3>(idx::p) = y.dp - x.dp;
    d.segment<3>(idx::v) = y.dv - x.dv;
    d.segment<3>(idx::ba) = x.dba - y.dba;
    d.segment<3>(idx::bg) = x.dbg - y.dbg;
  }

  bool jacobian_to_reference(const PreintIncrement&, Mat15& J) const noexcept override {
    SignedBiasSwap(J);
    return true;
  }

  bool jacobian_from_reference(const PreintIncrement&, Mat15& J) const noexcept override {
    SignedBiasSwap(J);
    return true;
  }
};

}  // namespace

IMUCONV_PLUGIN(PreintConvention, GtsamManifoldJacobian, "gtsam_manifold_jacobian", "1.0.0",
               "GTSAM preintegration bias-Jacobian chart (paper's j): dR Exp(dtheta), dp + dp, dv + dv, Db - db; "
               "[theta,p,v,ba,bg]")
