// imuconv refcase --anchor (see anchor.h): each anchor's computed fields, built from the case
// with that anchor's input conventions (tests/data/reference/anchors/README.md).
#include "anchor.h"

#include <Eigen/Geometry>
#include <cmath>
#include <utility>

#include "imuconv/kernels/basalt.h"
#include "imuconv/kernels/basalt_residual.h"
#include "imuconv/kernels/vins_fusion.h"
#include "imuconv/kernels/vins_fusion_residual.h"
#include "imuconv/printable.h"
#include "imuconv/so3.h"
#include "imuconv/window.h"
#include "refcase.h"

namespace imuconv::refcase {
namespace {

using json = nlohmann::json;
using namespace imuconv::kernels;

/// The whole case, first sample to last, at the bias estimate given.
PreintegrationInput Input(const Case& k, const Vec3& bg, const Vec3& ba) {
  PreintegrationInput in;
  const Status st = MakeWindow(k.samples.data(), k.samples.size(), k.samples.front().t,
                               k.samples.back().t, in.window);
  if (!st.ok()) throw Error("/imu: " + st.message());
  in.bg = bg;
  in.ba = ba;
  in.noise = k.noise;
  return in;
}

void Require(const Status& st, const char* what) {
  if (!st.ok()) throw Error(std::string(what) + ": " + st.message());
}

json Wxyz(const Eigen::Quaterniond& q) { return json::array({q.w(), q.x(), q.y(), q.z()}); }

/// The rotation Exp(dtheta) as a quaternion with w >= 0.
Eigen::Quaterniond QuaternionExp(const Vec3& dtheta) {
  const Eigen::Vector4d q = so3::ToQuaternionWxyz(so3::Exp(dtheta));
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
}

// ---- vins-fusion -----------------------------------------------------------------------

json VinsStateJson(const VinsFusionFactorState& x) {
  return {{"P", ToJsonVec(x.P)}, {"Q_wxyz", Wxyz(x.Q)},   {"R", ToJson(x.Q.toRotationMatrix())},
          {"V", ToJsonVec(x.V)}, {"Ba", ToJsonVec(x.Ba)}, {"Bg", ToJsonVec(x.Bg)}};
}

json VinsOutputJson(const VinsFusionFactorOutput& o) {
  return {{"residual", ToJsonVec(o.residual)},
          {"jacobian_pose_i", ToJson(o.jacobian_pose_i)},
          {"jacobian_speedbias_i", ToJson(o.jacobian_speedbias_i)},
          {"jacobian_pose_j", ToJson(o.jacobian_pose_j)},
          {"jacobian_speedbias_j", ToJson(o.jacobian_speedbias_j)}};
}

json VinsIntegrationJson(const VinsFusionPreintegration& r) {
  return {{"sum_dt", r.sum_dt},
          {"delta_p", ToJsonVec(r.delta_p)},
          {"delta_q_wxyz", Wxyz(r.delta_q)},
          {"delta_v", ToJsonVec(r.delta_v)},
          {"jacobian", ToJson(r.jacobian)},
          {"covariance", ToJson(r.covariance)}};
}

json VinsFusion(const Case& k) {
  // The anchor's inputs: the densities as configured, the start biases as the linearization
  // point, G = -gravity.
  VinsFusionMeasurement m;
  m.linearized_ba = k.x_s.ba;
  m.linearized_bg = k.x_s.bg;
  m.G = -k.gravity;
  Require(IntegrateVinsFusion(Input(k, k.x_s.bg, k.x_s.ba), VinsNoiseMapping::kAsConfigured, m.pre),
          "VINS-Fusion preintegration");
  json out = VinsIntegrationJson(m.pre);
  out["delta_R"] = ToJson(m.pre.delta_q.toRotationMatrix());

  VinsFusionFactorState i;
  i.P = k.x_s.p;
  i.Q = Eigen::Quaterniond(k.q_s_wxyz[0], k.q_s_wxyz[1], k.q_s_wxyz[2], k.q_s_wxyz[3]);
  i.V = k.x_s.v;
  i.Ba = k.x_s.ba;
  i.Bg = k.x_s.bg;
  // The relation evaluate() encodes, solved for state j.
  const double T = m.pre.sum_dt;
  VinsFusionFactorState pred = i;
  pred.P = i.P + i.V * T - 0.5 * m.G * T * T + i.Q * m.pre.delta_p;
  pred.V = i.V - m.G * T + i.Q * m.pre.delta_v;
  pred.Q = i.Q * m.pre.delta_q;
  out["predict"] = VinsStateJson(pred);
  out["residual_at_predict"] = ToJsonVec(VinsFusionEvaluate(m, i, pred));

  // End state: the prediction retracted by end_perturbation [dth, dp, dv, dbg, dba].
  const Vec15& e = k.end_perturbation;
  const Mat3 R_pred = pred.Q.toRotationMatrix();
  VinsFusionFactorState j = pred;
  j.Q = pred.Q * QuaternionExp(e.segment<3>(0));
  j.P = pred.P + R_pred * e.segment<3>(3);
  j.V = pred.V + R_pred * e.segment<3>(6);
  j.Bg = i.Bg + e.segment<3>(9);
  j.Ba = i.Ba + e.segment<3>(12);

  const VinsFusionFactorOutput raw = VinsFusionRawFactor(m, i, j);
  Mat15 sqrt_info;
  Require(VinsFusionSqrtInfo(m.pre.covariance, sqrt_info), "VINS-Fusion sqrt_info");
  out["factor"] = {{"state_i", VinsStateJson(i)},
                   {"state_j", VinsStateJson(j)},
                   {"evaluate_residual", ToJsonVec(VinsFusionEvaluate(m, i, j))},
                   {"raw", VinsOutputJson(raw)},
                   {"sqrt_info", ToJson(sqrt_info)},
                   {"whitened", VinsOutputJson(VinsFusionWhiten(raw, sqrt_info))}};

  VinsFusionFactorState i_new = i;
  i_new.Ba = k.x_s.ba + k.dba;
  i_new.Bg = k.x_s.bg + k.dbg;
  const VinsFusionCorrectedDelta c = VinsFusionCorrect(m, i_new.Ba, i_new.Bg);
  VinsFusionPreintegration re;
  Require(IntegrateVinsFusion(Input(k, i_new.Bg, i_new.Ba), VinsNoiseMapping::kAsConfigured, re),
          "VINS-Fusion repropagation");
  out["bias_correction"] = {{"Ba_new", ToJsonVec(i_new.Ba)},
                            {"Bg_new", ToJsonVec(i_new.Bg)},
                            {"first_order",
                             {{"corrected_delta_p", ToJsonVec(c.delta_p)},
                              {"corrected_delta_q_wxyz_unnormalized", Wxyz(c.delta_q)},
                              {"corrected_delta_v", ToJsonVec(c.delta_v)}}},
                            {"state_i", VinsStateJson(i_new)},
                            {"evaluate_residual", ToJsonVec(VinsFusionEvaluate(m, i_new, j))},
                            {"raw", VinsOutputJson(VinsFusionRawFactor(m, i_new, j))},
                            {"repropagated", VinsIntegrationJson(re)}};
  return out;
}

// ---- basalt ----------------------------------------------------------------------------

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
  return {{"R", ToJson(s.x.R)},
          {"p", ToJsonVec(s.x.p)},
          {"q_wxyz", Wxyz(s.q)},
          {"t_ns", s.t_ns},
          {"v", ToJsonVec(s.x.v)}};
}

json BasaltResidualJson(const BasaltResidual& r) {
  return {{"residual", ToJsonVec(r.residual)},
          {"d_res_d_state0", ToJson(r.d_res_d_state0)},
          {"d_res_d_state1", ToJson(r.d_res_d_state1)},
          {"d_res_d_bg", ToJson(r.d_res_d_bg)},
          {"d_res_d_ba", ToJson(r.d_res_d_ba)}};
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

json Basalt(const Case& k) {
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
  s0.q =
      Eigen::Quaterniond(k.q_s_wxyz[0], k.q_s_wxyz[1], k.q_s_wxyz[2], k.q_s_wxyz[3]).normalized();
  s0.t_ns = std::llround(k.samples.front().t * 1e9);  // Basalt's integer nanoseconds
  json out;
  out["native"] = BasaltFeedingJson(k, BasaltFeeding::kNative, variances, s0);
  out["forward_zoh"] = BasaltFeedingJson(k, BasaltFeeding::kForwardZoh, variances, s0);
  return out;
}

// ---- openvins --------------------------------------------------------------------------

json OpenVins(const Registry& reg, const Case& k) {
  PropagationInput in;
  in.x_s = k.x_s;
  in.noise = k.noise;
  in.gravity = k.gravity;
  in.window = Input(k, k.x_s.bg, k.x_s.ba).window;
  // P0: cov_s_left in OpenVINS's error state (theta_I = R^T dtheta_world, order changed).
  const Mat15 P0 = reg.convert_covariance("left", "openvins_jpl", k.x_s, k.cov_s_left);
  double dt_summed = 0.0;
  for (std::size_t s = 0; s + 1 < k.samples.size(); ++s)
    dt_summed += k.samples[s + 1].t - k.samples[s].t;

  json out, written = json::array(), missing = json::array();
  const std::pair<const char*, const char*> methods[] = {{"discrete", "openvins_discrete"},
                                                         {"rk4", "openvins_rk4"},
                                                         {"analytical", "openvins_analytical"}};
  for (const auto& [key, id] : methods) {
    if (!reg.has(PluginKind::Propagator, id)) {
      missing.push_back(id);
      continue;
    }
    in.cov_s = P0;
    const PropagationResult r = reg.propagate(id, "openvins_jpl", in);
    in.cov_s.setZero();  // Qd_summed: the noise alone
    const PropagationResult q = reg.propagate(id, "openvins_jpl", in);
    const Eigen::Vector4d q_wxyz = so3::ToQuaternionWxyz(r.x_e.R);  // OpenVINS keeps w >= 0
    out[key] = {{"state_end",
                 {{"q_GtoI_jpl_xyzw", json::array({q_wxyz[1], q_wxyz[2], q_wxyz[3], q_wxyz[0]})},
                  {"q_wxyz_body_to_world", ToJsonVec(q_wxyz)},
                  {"R_GtoI", ToJson(r.x_e.R.transpose())},
                  {"p_IinG", ToJsonVec(r.x_e.p)},
                  {"v_IinG", ToJsonVec(r.x_e.v)},
                  {"bg", ToJsonVec(r.x_e.bg)},
                  {"ba", ToJsonVec(r.x_e.ba)}}},
                {"covariance", ToJson(r.cov)},
                {"Phi_summed", ToJson(r.Phi)},
                {"Qd_summed", ToJson(q.cov)},
                {"dt_summed", dt_summed}};
    written.push_back(id);
  }
  if (written.empty())
    throw Error(
        "no OpenVINS propagator is registered (openvins_discrete, openvins_rk4, "
        "openvins_analytical)");
  out["methods_written"] = written;
  out["methods_missing"] = missing;
  return out;
}

}  // namespace

const std::vector<std::string>& AnchorNames() {
  static const std::vector<std::string> names = {"vins-fusion", "basalt", "openvins"};
  return names;
}

json RunAnchor(const Registry& reg, const json& case_json, const std::string& name) {
  if (name != "vins-fusion" && name != "basalt" && name != "openvins")
    throw Error("--anchor: unknown anchor '" + Printable(name) +
                "'; expected vins-fusion, basalt or openvins");
  const Case k = ParseCase(case_json);
  json out = name == "vins-fusion" ? VinsFusion(k)
             : name == "basalt"    ? Basalt(k)
                                   : OpenVins(reg, k);
  out["case_id"] = case_json.contains("case_id") ? case_json.at("case_id") : json("");
  out["anchor"] = name;
  out["generator"] = "imuconv refcase --anchor";
  CheckResults(out, "");
  return out;
}

}  // namespace imuconv::refcase
