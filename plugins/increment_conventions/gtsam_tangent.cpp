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
#include "imuconv/plugin_abi.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace {

using imuconv::Mat15;
using imuconv::PreintIncrement;
using imuconv::Vec15;
using imuconv::Vec3;
namespace so3 = imuconv::so3;
namespace ref = imuconv::pref_idx;

namespace idx {
constexpr int theta = 0, p = 3, v = 6, ba = 9, bg = 12;
}

class GtsamTangent final : public imuconv::PreintConvention {
 public:
  const char* id() const noexcept override { return "gtsam_tangent"; }
  imuconv::BlockLabels labels() const noexcept override { return {"theta", "p", "v", "ba", "bg"}; }

  void retract(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) const noexcept override {
    y.dR = so3::Exp(so3::Log(x.dR) + d.segment<3>(idx::theta));
    y.dp = x.dp + d.segment<3>(idx::p);
    y.dv = x.dv + d.segment<3>(idx::v);
    y.dba = x.dba - d.segment<3>(idx::ba);
    y.dbg = x.dbg - d.segment<3>(idx::bg);
  }

  void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept override {
    d.segment<3>(idx::theta) = so3::Log(y.dR) - so3::Log(x.dR);
    d.segment<3>(idx::p) = y.dp - x.dp;
    d.segment<3>(idx::v) = y.dv - x.dv;
    d.segment<3>(idx::ba) = x.dba - y.dba;
    d.segment<3>(idx::bg) = x.dbg - y.dbg;
  }

  bool jacobian_to_reference(const PreintIncrement& x, Mat15& J) const noexcept override {
    J.setZero();
    J.block<3, 3>(ref::theta, idx::theta) = so3::Jr(so3::Log(x.dR));
    J.block<3, 3>(ref::p, idx::p).setIdentity();
    J.block<3, 3>(ref::v, idx::v).setIdentity();
    J.block<3, 3>(ref::ba, idx::ba) = -Eigen::Matrix3d::Identity();
    J.block<3, 3>(ref::bg, idx::bg) = -Eigen::Matrix3d::Identity();
    return true;
  }

  bool jacobian_from_reference(const PreintIncrement& x, Mat15& J) const noexcept override {
    J.setZero();
    J.block<3, 3>(idx::theta, ref::theta) = so3::JrInv(so3::Log(x.dR));
    J.block<3, 3>(idx::p, ref::p).setIdentity();
    J.block<3, 3>(idx::v, ref::v).setIdentity();
    J.block<3, 3>(idx::ba, ref::ba) = -Eigen::Matrix3d::Identity();
    J.block<3, 3>(idx::bg, ref::bg) = -Eigen::Matrix3d::Identity();
    return true;
  }
};

}  // namespace

IMUCONV_PLUGIN(PreintConvention, GtsamTangent, "gtsam_tangent", "1.0.0",
               "GTSAM TangentPreintegration: Exp(Log dR + dtheta), dp + dp, dv + dv, Db - db; [theta,p,v,ba,bg]")
