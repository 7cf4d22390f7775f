// `left_invariant_se23`: the left-invariant error of the invariant EKF (Barrau and
// Bonnabel, IEEE TAC 2017; Hartley et al., IJRR 2020). (R, v, p) is one element of SE_2(3),
//   X = [[R, v, p], [0, 1, 0], [0, 0, 1]],
// perturbed on the right by the group exponential, X = X^ Exp(xi), xi = [phi, nu, rho]; the
// error X^{-1} X is invariant to left multiplication and lives in the body frame:
//   R = R^ Exp(phi),  v = v^ + R^ Jl(phi) nu,  p = p^ + R^ Jl(phi) rho,  b = b^ + db,
// order [theta, v, p, bg, ba]. local: phi = Log(R^T R_y), nu = Jl^{-1}(phi) R^T (v_y - v^),
// rho likewise. It is right_invariant_se23 transported by the adjoint of X^:
// Exp(Ad_X xi) X = X Exp(xi).
//
// Against `left`: dtheta_l = R^ phi exactly; dv_l = R^ Jl(phi) nu and dp_l = R^ Jl(phi) rho,
// whose derivatives at 0 are R^ (the phi-derivative multiplies nu = rho = 0).
#include "imuconv/plugin_abi.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace {

using imuconv::ImuState;
using imuconv::Mat15;
using imuconv::Mat3;
using imuconv::Vec15;
using imuconv::Vec3;
namespace so3 = imuconv::so3;
namespace ref = imuconv::left_idx;

namespace idx {
constexpr int theta = 0, v = 3, p = 6, bg = 9, ba = 12;
}

class LeftInvariantSe23 final : public imuconv::ErrorState {
 public:
  const char* id() const noexcept override { return "left_invariant_se23"; }
  imuconv::BlockLabels labels() const noexcept override { return {"theta", "v", "p", "bg", "ba"}; }

  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    const Vec3 phi = d.segment<3>(idx::theta);
    const Mat3 RV = x.R * so3::Jl(phi);
    y.R = x.R * so3::Exp(phi);
    y.v = x.v + RV * d.segment<3>(idx::v);
    y.p = x.p + RV * d.segment<3>(idx::p);
    y.bg = x.bg + d.segment<3>(idx::bg);
    y.ba = x.ba + d.segment<3>(idx::ba);
  }

  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    const Mat3 Rt = x.R.transpose();
    const Vec3 phi = so3::Log(Rt * y.R);
    const Mat3 VinvRt = so3::JlInv(phi) * Rt;
    d.segment<3>(idx::theta) = phi;
    d.segment<3>(idx::v) = VinvRt * (y.v - x.v);
    d.segment<3>(idx::p) = VinvRt * (y.p - x.p);
    d.segment<3>(idx::bg) = y.bg - x.bg;
    d.segment<3>(idx::ba) = y.ba - x.ba;
  }

  bool jacobian_to_reference(const ImuState& x, Mat15& J) const noexcept override {
    J.setZero();
    J.block<3, 3>(ref::theta, idx::theta) = x.R;
    J.block<3, 3>(ref::v, idx::v) = x.R;
    J.block<3, 3>(ref::p, idx::p) = x.R;
    J.block<3, 3>(ref::bg, idx::bg).setIdentity();
    J.block<3, 3>(ref::ba, idx::ba).setIdentity();
    return true;
  }

  bool jacobian_from_reference(const ImuState& x, Mat15& J) const noexcept override {
    const Mat3 Rt = x.R.transpose();
    J.setZero();
    J.block<3, 3>(idx::theta, ref::theta) = Rt;
    J.block<3, 3>(idx::v, ref::v) = Rt;
    J.block<3, 3>(idx::p, ref::p) = Rt;
    J.block<3, 3>(idx::bg, ref::bg).setIdentity();
    J.block<3, 3>(idx::ba, ref::ba).setIdentity();
    return true;
  }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, LeftInvariantSe23, "left_invariant_se23", "1.0.0",
               "InEKF left-invariant SE_2(3) error: X = X^ Exp(xi), b + db; [theta,v,p,bg,ba]")
