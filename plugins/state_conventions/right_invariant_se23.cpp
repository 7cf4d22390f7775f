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
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

namespace {

using namespace imuconv::plugin::prelude;

constexpr BlockOrder kOrder{Block::theta, Block::v, Block::p, Block::bg, Block::ba};

class RightInvariantSe23 : public imuconv::plugin::StateChart<kOrder> {
 public:
  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    const Vec3 phi = d.segment<3>(theta);
    const Mat3 E = so3::Exp(phi);
    const Mat3 V = so3::Jl(phi);
    y.R = E * x.R;
    y.v = E * x.v + V * d.segment<3>(v);
    y.p = E * x.p + V * d.segment<3>(p);
    RetractBiases(x, d, y);
  }

  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    const Mat3 E = y.R * x.R.transpose();  // = Exp(phi)
    const Vec3 phi = so3::Log(E);
    const Mat3 Vinv = so3::JlInv(phi);
    d.segment<3>(theta) = phi;
    d.segment<3>(v) = Vinv * (y.v - E * x.v);
    d.segment<3>(p) = Vinv * (y.p - E * x.p);
    LocalBiases(x, y, d);
  }

  // dtheta_l = phi, dv_l = nu - [v^]x phi, dp_l = rho - [p^]x phi.
  bool J_ref_this(const ImuState& x, Mat15& J) const noexcept override {
    RefThis(J, {});
    RefThisBlock(J, Block::v, Block::theta) = -so3::skew(x.v);
    RefThisBlock(J, Block::p, Block::theta) = -so3::skew(x.p);
    return true;
  }

  // The inverse: phi = dtheta_l, nu = dv_l + [v^]x dtheta_l, rho = dp_l + [p^]x dtheta_l.
  bool J_this_ref(const ImuState& x, Mat15& J) const noexcept override {
    ThisRef(J, {});
    ThisRefBlock(J, Block::v, Block::theta) = so3::skew(x.v);
    ThisRefBlock(J, Block::p, Block::theta) = so3::skew(x.p);
    return true;
  }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, RightInvariantSe23, "right_invariant_se23", "1.0.0",
               "InEKF right-invariant SE_2(3) error: X = Exp(xi) X^, b + db; [theta,v,p,bg,ba]")
