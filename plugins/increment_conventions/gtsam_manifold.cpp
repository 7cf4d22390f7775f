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
// "GTSAM Peculiarities"), hence jacobian_convention().
//
// Against `preint_reference`: dtheta_r = dtheta, dp_r = Delta R^ dp, dv_r = Delta R^ dv
// exactly; bias blocks -I with ba and bg swapped.
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

namespace {

using namespace imuconv::plugin::prelude;

// GTSAM's order, accelerometer bias first.
constexpr BlockOrder kOrder{Block::theta, Block::p, Block::v, Block::ba, Block::bg};
constexpr std::array kBodyFrame{Block::p, Block::v};  // the reference's blocks rotated by Delta R^T

class GtsamManifold
    : public imuconv::plugin::RightRotationChart<imuconv::plugin::IncrementChart<kOrder, -1>,
                                                 kBodyFrame> {
 public:
  const char* jacobian_convention() const noexcept override { return "gtsam_manifold_jacobian"; }
};

}  // namespace

IMUCONV_PLUGIN(IncrementConvention, GtsamManifold, "gtsam_manifold", "1.0.0",
               "GTSAM ManifoldPreintegration covariance (paper's c): dR Exp(dtheta), dp + dR dp, "
               "dv + dR dv, Db - db; "
               "[theta,p,v,ba,bg]")
