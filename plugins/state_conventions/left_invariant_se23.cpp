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
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

namespace {

using namespace imuconv::plugin::prelude;

constexpr BlockOrder kOrder{Block::theta, Block::v, Block::p, Block::bg, Block::ba};
constexpr std::array kBodyFrame{Block::theta, Block::v,
                                Block::p};  // left's blocks rotated by R^T (to first order)

class LeftInvariantSe23
    : public imuconv::plugin::RotatedBlocksChart<imuconv::plugin::StateChart<kOrder>, kBodyFrame> {
 public:
  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    const Vec3 phi = d.segment<3>(theta);
    const Mat3 RV = x.R * so3::Jl(phi);
    y.R = x.R * so3::Exp(phi);
    y.v = x.v + RV * d.segment<3>(v);
    y.p = x.p + RV * d.segment<3>(p);
    RetractBiases(x, d, y);
  }

  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    const Mat3 Rt = x.R.transpose();
    const Vec3 phi = so3::Log(Rt * y.R);
    const Mat3 VinvRt = so3::JlInv(phi) * Rt;
    d.segment<3>(theta) = phi;
    d.segment<3>(v) = VinvRt * (y.v - x.v);
    d.segment<3>(p) = VinvRt * (y.p - x.p);
    LocalBiases(x, y, d);
  }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, LeftInvariantSe23, "left_invariant_se23", "1.0.0",
               "InEKF left-invariant SE_2(3) error: X = X^ Exp(xi), b + db; [theta,v,p,bg,ba]")
