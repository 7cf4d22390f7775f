// refcase --anchor basalt: see anchor.h for what the fields are.
#include <Eigen/Geometry>
#include <cmath>
#include <utility>

#include "anchor_writer.h"
#include "imuconv/kernels/basalt.h"
#include "imuconv/kernels/basalt_residual.h"

namespace imuconv::refcase {
namespace {

using json = nlohmann::json;
using namespace imuconv::kernels;
using namespace anchor_support;

constexpr double kBasaltImuRate =
    200.0;  // imu_update_rate of the anchors (the cases' nominal rate)

/// A Basalt state with its quaternion (kept beside the matrix so that its sign is the one a
/// product of Sophus rotations has) and time.
struct BasaltStateOut {
  BasaltPoseVelState x;
  Eigen::Quaterniond q;
  long long t_ns = 0;
};

json BasaltStateJson(const BasaltStateOut& s) {
  return {{"q_wxyz", Wxyz(s.q)},
          {"t_ns", s.t_ns},
          IMUCONV_ANCHOR_MEMBERS(FieldJson, s.x, (R)(p)(v))};
}

json BasaltResidualJson(const BasaltResidual& r) {
  return {IMUCONV_ANCHOR_MEMBERS(
      FieldJson, r, (residual)(d_res_d_state0)(d_res_d_state1)(d_res_d_bg)(d_res_d_ba))};
}

/// The delta state as getDeltaState() returns it; its quaternion with w >= 0 (a product of
/// exponentials of small steps, as Sophus forms it, stays there unless the path turns by more
/// than pi).
BasaltStateOut BasaltDelta(const BasaltPreintegration& r) {
  BasaltStateOut d;
  d.x.R = r.R;
  d.x.p = r.p;
  d.x.v = r.v;
  const Eigen::Vector4d q = so3::ToQuaternionWxyz(r.R);
  d.q = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  d.t_ns = r.dt_ns;
  return d;
}

json BasaltFeedingJson(const Case& k, BasaltFeeding feeding, const BasaltSampleVariances& variances,
                       const BasaltStateOut& s0) {
  BasaltMeasurement m;
  m.bias_gyro_lin = k.x_s.bg;
  m.bias_accel_lin = k.x_s.ba;
  Require(IntegrateBasalt(Input(k, k.x_s.bg, k.x_s.ba), feeding, variances, m.pre),
          "Basalt preintegration");
  json out;
  out["start_t_ns"] = s0.t_ns;
  out["dt_ns"] = m.pre.dt_ns;
  const BasaltStateOut delta = BasaltDelta(m.pre);
  out["delta_state"] = BasaltStateJson(delta);
  out["cov"] = ToJson(m.pre.cov);
  out["d_state_d_ba"] = ToJson(m.pre.d_state_d_ba);
  out["d_state_d_bg"] = ToJson(m.pre.d_state_d_bg);

  // predictState(state0, g).
  const double T = static_cast<double>(m.pre.dt_ns) * 1e-9;
  const Vec3& g = k.gravity;
  BasaltStateOut pred;
  pred.x.R = s0.x.R * m.pre.R;
  pred.x.v = s0.x.v + g * T + s0.x.R * m.pre.v;
  pred.x.p = s0.x.p + s0.x.v * T + 0.5 * g * T * T + s0.x.R * m.pre.p;
  pred.q = s0.q * delta.q;
  pred.t_ns = s0.t_ns + m.pre.dt_ns;
  out["predict"] = BasaltStateJson(pred);
  out["residual_at_predict"] =
      ToJsonVec(BasaltResidualOf(m, s0.x, g, pred.x, k.x_s.bg, k.x_s.ba).residual);

  // End state: the prediction retracted by end_perturbation [dth, dp, dv, ...].
  const Vec15& e = k.end_perturbation;
  BasaltStateOut s1 = pred;
  s1.x.R = pred.x.R * so3::Exp(e.segment<3>(0));
  s1.q = pred.q * QuaternionExp(e.segment<3>(0));
  s1.x.p = pred.x.p + pred.x.R * e.segment<3>(3);
  s1.x.v = pred.x.v + pred.x.R * e.segment<3>(6);
  const Vec3 bg_new = k.x_s.bg + k.dbg, ba_new = k.x_s.ba + k.dba;
  out["factor"] = {
      {"state0", BasaltStateJson(s0)},
      {"state1", BasaltStateJson(s1)},
      {"curr_bg", ToJsonVec(k.x_s.bg)},
      {"curr_ba", ToJsonVec(k.x_s.ba)},
      {"curr_bg_new", ToJsonVec(bg_new)},
      {"curr_ba_new", ToJsonVec(ba_new)},
      {"at_lin_bias", BasaltResidualJson(BasaltResidualOf(m, s0.x, g, s1.x, k.x_s.bg, k.x_s.ba))},
      {"at_new_bias", BasaltResidualJson(BasaltResidualOf(m, s0.x, g, s1.x, bg_new, ba_new))}};

  const BasaltPoseVelState c = BasaltCorrectedDelta(m, bg_new, ba_new);
  BasaltPreintegration re;
  Require(IntegrateBasalt(Input(k, bg_new, ba_new), feeding, variances, re, false),
          "Basalt re-integration");
  out["bias_correction"] = {
      {"bg_new", ToJsonVec(bg_new)},
      {"ba_new", ToJsonVec(ba_new)},
      {"first_order", {{"R", ToJson(c.R)}, {"p", ToJsonVec(c.p)}, {"v", ToJsonVec(c.v)}}},
      {"reintegrated", BasaltStateJson(BasaltDelta(re))}};
  return out;
}

json Basalt(const Registry&, const Case& k) {
  // Basalt's VIO: dicrete_time_*_noise_std()^2 = density^2 x imu_update_rate, per sample.
  BasaltSampleVariances variances;
  variances.accel.setConstant(k.noise.accel_noise_density * k.noise.accel_noise_density *
                              kBasaltImuRate);
  variances.gyro.setConstant(k.noise.gyro_noise_density * k.noise.gyro_noise_density *
                             kBasaltImuRate);
  BasaltStateOut s0;
  s0.x.R = k.x_s.R;
  s0.x.p = k.x_s.p;
  s0.x.v = k.x_s.v;
  s0.q = StartQuaternion(k).normalized();
  s0.t_ns = std::llround(k.samples.front().t * 1e9);  // Basalt's integer nanoseconds
  json out;
  out["native"] = BasaltFeedingJson(k, BasaltFeeding::kNative, variances, s0);
  out["forward_zoh"] = BasaltFeedingJson(k, BasaltFeeding::kForwardZoh, variances, s0);
  return out;
}

}  // namespace
}  // namespace imuconv::refcase

IMUCONV_ANCHOR_WRITER(basalt, "basalt", &Basalt)
