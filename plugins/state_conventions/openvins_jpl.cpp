// `openvins_jpl`: the IMU error state of OpenVINS (ov_msckf, ov_type::IMU / JPLQuat).
// OpenVINS stores the JPL quaternion q_GtoI (vector part first, global-to-IMU rotation) and
// updates it exactly as JPLQuat::update does: dq = normalize([dtheta / 2; 1]),
// q = dq (x) q^ (JPL product). p_IinG and v_IinG are updated additively in the global frame,
// the biases additively; order [theta, p, v, bg, ba] as in OpenVINS's IMU state vector.
//
// In body-to-world Hamilton terms: dq is a rotation by |phi| = 2 atan(|dtheta| / 2) about
// dtheta / |dtheta|, and a JPL quaternion's matrix is C(q) = R_GtoI = Exp(-phi) for that
// rotation, so R_GtoI = Exp(-phi) R^_GtoI, i.e.
//   R = R^ Exp(phi),  phi = 2 atan(|dtheta| / 2) dtheta / |dtheta|,
//   p = p^ + dp,  v = v^ + dv,  b = b^ + db.
// local inverts it: phi = Log(R^T R_y), dtheta = 2 tan(|phi| / 2) phi / |phi| (|phi| < pi).
// (its test file checks this against an independent JPL implementation.)
//
// Against `left`: phi = dtheta + O(|dtheta|^3), so dtheta_l = R^ dtheta to first order;
// dp_l = dp, dv_l = dv. The Jacobians equal those of the first-order error state OpenVINS
// linearises its filter in (R_GtoI ~ (I - [dtheta]x) R^_GtoI).
#include <cmath>

#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

namespace {

using namespace imuconv::plugin::prelude;

constexpr BlockOrder kOrder{Block::theta, Block::p, Block::v, Block::bg, Block::ba};

// Below this angle the ratios use their Taylor series (next term < 1e-18).
constexpr double kSeriesBelow = 1e-3;

// phi / dtheta = 2 atan(s / 2) / s with s = |dtheta|.
double AtanRatio(double s) {
  if (s < kSeriesBelow) {
    const double s2 = s * s;
    return 1.0 - s2 / 12.0 + s2 * s2 / 80.0;
  }
  return 2.0 * std::atan(0.5 * s) / s;
}

// dtheta / phi = 2 tan(t / 2) / t with t = |phi|.
double TanRatio(double t) {
  if (t < kSeriesBelow) {
    const double t2 = t * t;
    return 1.0 + t2 / 12.0 + t2 * t2 / 120.0;
  }
  return 2.0 * std::tan(0.5 * t) / t;
}

class OpenVinsJpl : public imuconv::plugin::StateChart<kOrder> {
 public:
  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    const Vec3 dtheta = d.segment<3>(theta);
    y.R = x.R * so3::Exp(AtanRatio(dtheta.norm()) * dtheta);
    y.p = x.p + d.segment<3>(p);
    y.v = x.v + d.segment<3>(v);
    RetractBiases(x, d, y);
  }

  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    const Vec3 phi = so3::Log(x.R.transpose() * y.R);
    d.segment<3>(theta) = TanRatio(phi.norm()) * phi;
    d.segment<3>(p) = y.p - x.p;
    d.segment<3>(v) = y.v - x.v;
    LocalBiases(x, y, d);
  }

  bool J_ref_this(const ImuState& x, Mat15& J) const noexcept override {
    return RefThis(J, {{Block::theta, x.R}});
  }
  bool J_this_ref(const ImuState& x, Mat15& J) const noexcept override {
    return ThisRef(J, {{Block::theta, x.R.transpose()}});
  }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, OpenVinsJpl, "openvins_jpl", "1.0.0",
               "OpenVINS JPL q_GtoI update dq(x)q, dq = [dtheta/2; 1] normalised; p, v, b "
               "additive; [theta,p,v,bg,ba]")
