// `forster`: the state perturbation of Forster, Carlone, Dellaert and Scaramuzza,
// "On-Manifold Preintegration for Real-Time Visual-Inertial Odometry", IEEE TRO 2017 (the
// retraction of the navigation state its IMU factor is linearised in), as quoted at the end
// of the paper's "Forster Preintegration" paragraph (after eq. forster-res-jac):
//   R = R^ Exp(dtheta),  p = p^ + R^ dp,  v = v^ + dv,  b = b^ + db,
// order [theta, p, v, bg, ba]. The position is perturbed in the body frame of the estimate
// R^ (the paper writes R, equal to first order), the velocity in the world frame.
//
// Against `left`: dtheta_l = R^ dtheta and dp_l = R^ dp exactly, dv_l = dv.
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

namespace idx {
constexpr int theta = 0, p = 3, v = 6, bg = 9, ba = 12;
}

class Forster final : public imuconv::ErrorState {
 public:
  const char* id() const noexcept override { return "forster"; }
  imuconv::BlockLabels labels() const noexcept override { return {"theta", "p", "v", "bg", "ba"}; }

  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    y.R = x.R * so3::Exp(d.segment<3>(idx::theta));
    y.p = x.p + x.R * d.segment<3>(idx::p);
    y.v = x.v + d.segment<3>(idx::v);
    y.bg = x.bg + d.segment<3>(idx::bg);
    y.ba = x.ba + d.segment<3>(idx::ba);
  }

  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    const Mat3 Rt = x.R.transpose();
    d.segment<3>(idx::theta) = so3::Log(Rt * y.R);
    d.segment<3>(idx::p) = Rt * (y.p - x.p);
    d.segment<3>(idx::v) = y.v - x.v;
    d.segment<3>(idx::bg) = y.bg - x.bg;
    d.segment<3>(idx::ba) = y.ba - x.ba;
  }

  bool jacobian_to_reference(const ImuState& x, Mat15& J) const noexcept override {
    J.setZero();
    J.block<3, 3>(ref::theta, idx::theta) = x.R;
    J.block<3, 3>(ref::p, idx::p) = x.R;
    J.block<3, 3>(ref::v, idx::v).setIdentity();
    J.block<3, 3>(ref::bg, idx::bg).setIdentity();
    J.block<3, 3>(ref::ba, idx::ba).setIdentity();
    return true;
  }

  bool jacobian_from_reference(const ImuState& x, Mat15& J) const noexcept override {
    const Mat3 Rt = x.R.transpose();
    J.setZero();
    J.block<3, 3>(idx::theta, ref::theta) = Rt;
    J.block<3, 3>(idx::p, ref::p) = Rt;
    J.block<3, 3>(idx::v, ref::v).setIdentity();
    J.block<3, 3>(idx::bg, ref::bg).setIdentity();
    J.block<3, 3>(idx::ba, ref::ba).setIdentity();
    return true;
  }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, Forster, "forster", "1.0.0",
               "Forster et al. TRO 2017: R Exp(dtheta), p + R dp, v + dv, b + db; [theta,p,v,bg,ba]")
