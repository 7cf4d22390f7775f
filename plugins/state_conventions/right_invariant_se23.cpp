// `right_invariant_se23`: the right-invariant error of the invariant EKF (Barrau and
// Bonnabel, "The Invariant Extended Kalman Filter as a Stable Observer", IEEE TAC 2017;
// Hartley et al., "Contact-Aided Invariant Extended Kalman Filtering for Robot State
// Estimation", IJRR 2020). (R, v, p) is one element of SE_2(3),
//   X = [[R, v, p], [0, 1, 0], [0, 0, 1]],
// perturbed on the left by the group exponential, X = Exp(xi) X^, xi = [phi, nu, rho]; the
// error X X^{-1} is invariant to right multiplication and lives in the world frame. With
// Exp(xi) = [[Exp(phi), Jl(phi) nu, Jl(phi) rho], ...]:
//   R = Exp(phi) R^,  v = Exp(phi) v^ + Jl(phi) nu,  p = Exp(phi) p^ + Jl(phi) rho,
//   b = b^ + db (biases outside the group, as in the "imperfect" InEKF),
// order [theta, v, p, bg, ba]. local: phi = Log(R_y R^T), nu = Jl^{-1}(phi) (v_y - R_y R^T v^),
// rho likewise.
//
// Against `left` (same rotation perturbation): dtheta_l = phi exactly, and to first order
// dv_l = [phi]x v^ + nu = nu - [v^]x phi, dp_l = rho - [p^]x phi.
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

class RightInvariantSe23 final : public imuconv::ErrorState {
 public:
  const char* id() const noexcept override { return "right_invariant_se23"; }
  imuconv::BlockLabels labels() const noexcept override { return {"theta", "v", "p", "bg", "ba"}; }

  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    const Vec3 phi = d.segment<3>(idx::theta);
    const Mat3 E = so3::Exp(phi);
    const Mat3 V = so3::Jl(phi);
    y.R = E * x.R;
    y.v = E * x.v + V * d.segment<3>(idx::v);
    y.p = E * x.p + V * d.segment<3>(idx::p);
    y.bg = x.bg + d.segment<3>(idx::bg);
    y.ba = x.ba + d.segment<3>(idx::ba);
  }

  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    const Mat3 E = y.R * x.R.transpose();  // = Exp(phi)
    const Vec3 phi = so3::Log(E);
    const Mat3 Vinv = so3::JlInv(phi);
    d.segment<3>(idx::theta) = phi;
    d.segment<3>(idx::v) = Vinv * (y.v - E * x.v);
    d.segment<3>(idx::p) = Vinv * (y.p - E * x.p);
    d.segment<3>(idx::bg) = y.bg - x.bg;
    d.segment<3>(idx::ba) = y.ba - x.ba;
  }

  // dtheta_l = phi, dv_l = nu - [v^]x phi, dp_l = rho - [p^]x phi.
  bool jacobian_to_reference(const ImuState& x, Mat15& J) const noexcept override {
    J.setZero();
    J.block<3, 3>(ref::theta, idx::theta).setIdentity();
    J.block<3, 3>(ref::v, idx::theta) = -so3::skew(x.v);
    J.block<3, 3>(ref::v, idx::v).setIdentity();
    J.block<3, 3>(ref::p, idx::theta) = -so3::skew(x.p);
    J.block<3, 3>(ref::p, idx::p).setIdentity();
    J.block<3, 3>(ref::bg, idx::bg).setIdentity();
    J.block<3, 3>(ref::ba, idx::ba).setIdentity();
    return true;
  }

  // The inverse: phi = dtheta_l, nu = dv_l + [v^]x dtheta_l, rho = dp_l + [p^]x dtheta_l.
  bool jacobian_from_reference(const ImuState& x, Mat15& J) const noexcept override {
    J.setZero();
    J.block<3, 3>(idx::theta, ref::theta).setIdentity();
    J.block<3, 3>(idx::v, ref::v).setIdentity();
    J.block<3, 3>(idx::p, ref::p).setIdentity();
    J.block<3, 3>(idx::v, ref::theta) = so3::skew(x.v);
    J.block<3, 3>(idx::p, ref::theta) = so3::skew(x.p);
    J.block<3, 3>(idx::bg, ref::bg).setIdentity();
    J.block<3, 3>(idx::ba, ref::ba).setIdentity();
    return true;
  }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, RightInvariantSe23, "right_invariant_se23", "1.0.0",
               "InEKF right-invariant SE_2(3) error: X = Exp(xi) X^, b + db; [theta,v,p,bg,ba]")
