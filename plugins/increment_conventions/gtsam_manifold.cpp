// `gtsam_manifold`: the chart of GTSAM ManifoldPreintegration's covariance preintMeasCov_,
// the paper's c perturbation (eq. residual-error): the increment (Delta R, dp, dv) is a
// gtsam::NavState perturbed by NavState::retract, the bias entry with the paper's sign:
//   Delta R = Delta R^ Exp(dtheta),  dp = dp^ + Delta R^ dp,  dv = dv^ + Delta R^ dv,
//   Delta b_a = Delta b_a^ - dba,  Delta b_g = Delta b_g^ - dbg,
// order [theta, p, v, ba, bg]. Like NavState::retract it rotates dp and dv by the
// estimate's Delta R^ (the paper writes Delta R, equal to first order).
//
// ManifoldPreintegration reports its bias Jacobians (delRdelBiasOmega, delPdelBiasAcc, ...)
// not in this chart but in the vector-space one of `gtsam_manifold_jacobian` (paper,
// "GTSAM Peculiarities"), hence bias_jacobian_chart().
//
// Against `preint_reference`: dtheta_r = dtheta, dp_r = Delta R^ dp, dv_r = Delta R^ dv
// exactly; bias blocks -I with ba and bg swapped.
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

class GtsamManifold final : public imuconv::PreintConvention {
 public:
  const char* id() const noexcept override { return "gtsam_manifold"; }
  imuconv::BlockLabels labels() const noexcept override { return {"theta", "p", "v", "ba", "bg"}; }
  const char* bias_jacobian_chart() const noexcept override { return "gtsam_manifold_jacobian"; }

  void retract(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) const noexcept override {
    y.dR = x.dR * so3::Exp(d.segment<3>(idx::theta));
    y.dp = x.dp + x.dR * d.segment<3>(idx::p);
    y.dv = x.dv + x.dR * d.segment<3>(idx::v);
    y.dba = x.dba - d.segment<3>(idx::ba);
    y.dbg = x.dbg - d.segment<3>(idx::bg);
  }

  void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept override {
    const Mat3 Rt = x.dR.transpose();
    d.segment<3>(idx::theta) = so3::Log(Rt * y.dR);
    d.segment<3>(idx::p) = Rt * (y.dp - x.dp);
    d.segment<3>(idx::v) = Rt * (y.dv - x.dv);
    d.segment<3>(idx::ba) = x.dba - y.dba;
    d.segment<3>(idx::bg) = x.dbg - y.dbg;
  }

  bool jacobian_to_reference(const PreintIncrement& x, Mat15& J) const noexcept override {
    J.setZero();
    J.block<3, 3>(ref::theta, idx::theta).setIdentity();
    J.block<3, 3>(ref::p, idx::p) = x.dR;
    J.block<3, 3>(ref::v, idx::v) = x.dR;
    J.block<3, 3>(ref::ba, idx::ba) = -Mat3::Identity();
    J.block<3, 3>(ref::bg, idx::bg) = -Mat3::Identity();
    return true;
  }

  bool jacobian_from_reference(const PreintIncrement& x, Mat15& J) const noexcept override {
    const Mat3 Rt = x.dR.transpose();
    J.setZero();
    J.block<3, 3>(idx::theta, ref::theta).setIdentity();
    J.block<3, 3>(idx::p, ref::p) = Rt;
    J.block<3, 3>(idx::v, ref::v) = Rt;
    J.block<3, 3>(idx::ba, ref::ba) = -Mat3::Identity();
    J.block<3, 3>(idx::bg, ref::bg) = -Mat3::Identity();
    return true;
  }
};

}  // namespace

IMUCONV_PLUGIN(PreintConvention, GtsamManifold, "gtsam_manifold", "1.0.0",
               "GTSAM ManifoldPreintegration covariance (paper's c): dR Exp(dtheta), dp + dR dp, dv + dR dv, Db - db; "
               "[theta,p,v,ba,bg]")
