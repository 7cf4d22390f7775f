// `gtsam_navstate`: the chart of gtsam::NavState::retract / localCoordinates (the state of
// GTSAM's ImuFactor2 and of PreintegrationBase::predict), with the biases of
// gtsam::imuBias::ConstantBias added, accelerometer first. Paper eq.
// subeq:navstate-drp..subeq:navstate-dbg:
//   R = R^ Exp(dtheta),  p = p^ + R^ dp,  v = v^ + R^ dv,  ba = ba^ + dba,  bg = bg^ + dbg,
// order [theta, p, v, ba, bg]. NavState rotates dp and dv by the estimate's rotation R^
// (the paper writes R, which agrees to first order); this makes the chart an exact
// product of a right SO(3) perturbation and two body-frame translations.
//
// Against `left` (p + dp_l, Exp(dtheta_l) R, v + dv_l): R^ Exp(dtheta) = Exp(R^ dtheta) R^,
// so dtheta_l = R^ dtheta, dp_l = R^ dp, dv_l = R^ dv exactly; the Jacobians are
// block-diagonal rotations plus a bias permutation.
#include "imuconv/plugin_abi.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace {

using imuconv::ImuState;
using imuconv::Mat15;
using imuconv::Mat3;
using imuconv::Vec15;
namespace so3 = imuconv::so3;
namespace ref = imuconv::left_idx;

// Block offsets of this chart.
namespace idx {
constexpr int theta = 0, p = 3, v = 6, ba = 9, bg = 12;
}

class GtsamNavState final : public imuconv::ErrorState {
 public:
  const char* id() const noexcept override { return "gtsam_navstate"; }
  imuconv::BlockLabels labels() const noexcept override { return {"theta", "p", "v", "ba", "bg"}; }

  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    y.R = x.R * so3::Exp(d.segment<3>(idx::theta));
    y.p = x.p + x.R * d.segment<3>(idx::p);
    y.v = x.v + x.R * d.segment<3>(idx::v);
    y.ba = x.ba + d.segment<3>(idx::ba);
    y.bg = x.bg + d.segment<3>(idx::bg);
  }

  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    const Mat3 Rt = x.R.transpose();
    d.segment<3>(idx::theta) = so3::Log(Rt * y.R);
    d.segment<3>(idx::p) = Rt * (y.p - x.p);
    d.segment<3>(idx::v) = Rt * (y.v - x.v);
    d.segment<3>(idx::ba) = y.ba - x.ba;
    d.segment<3>(idx::bg) = y.bg - x.bg;
  }

  // dtheta_l = R^ dtheta, dp_l = R^ dp, dv_l = R^ dv, biases permuted.
  bool jacobian_to_reference(const ImuState& x, Mat15& J) const noexcept override {
    J.setZero();
    J.block<3, 3>(ref::theta, idx::theta) = x.R;
    J.block<3, 3>(ref::p, idx::p) = x.R;
    J.block<3, 3>(ref::v, idx::v) = x.R;
    J.block<3, 3>(ref::ba, idx::ba).setIdentity();
    J.block<3, 3>(ref::bg, idx::bg).setIdentity();
    return true;
  }

  // The inverse: R^T on the three motion blocks.
  bool jacobian_from_reference(const ImuState& x, Mat15& J) const noexcept override {
    const Mat3 Rt = x.R.transpose();
    J.setZero();
    J.block<3, 3>(idx::theta, ref::theta) = Rt;
    J.block<3, 3>(idx::p, ref::p) = Rt;
    J.block<3, 3>(idx::v, ref::v) = Rt;
    J.block<3, 3>(idx::ba, ref::ba).setIdentity();
    J.block<3, 3>(idx::bg, ref::bg).setIdentity();
    return true;
  }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, GtsamNavState, "gtsam_navstate", "1.0.0",
               "gtsam::NavState::retract: R Exp(dtheta), p + R dp, v + R dv, b + db; [theta,p,v,ba,bg]")
