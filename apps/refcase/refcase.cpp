#include "refcase.h"

#include <string>
#include <vector>

#include "imuconv/bridge.h"
#include "imuconv/so3.h"

namespace imuconv::refcase {
namespace {

using json = nlohmann::json;

const json& At(const json& j, const std::string& key, const std::string& ptr) {
  if (!j.is_object() || !j.contains(key)) throw Error(ptr + "/" + key + ": missing");
  return j.at(key);
}

double Number(const json& j, const std::string& ptr) {
  if (!j.is_number()) throw Error(ptr + ": expected a number");
  return j.get<double>();
}

Vec3 Vector3(const json& j, const std::string& ptr) {
  if (!j.is_array() || j.size() != 3) throw Error(ptr + ": expected an array of 3 numbers");
  return Vec3(Number(j[0], ptr + "/0"), Number(j[1], ptr + "/1"), Number(j[2], ptr + "/2"));
}

json ToJson(const Eigen::MatrixXd& m) {
  json rows = json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    json row = json::array();
    for (Eigen::Index k = 0; k < m.cols(); ++k) row.push_back(m(i, k));
    rows.push_back(row);
  }
  return rows;
}

json ToJsonVec(const Eigen::VectorXd& v) {
  json a = json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v[i]);
  return a;
}

json NavJson(const ImuState& x) { return {{"R", ToJson(x.R)}, {"p", ToJsonVec(x.p)}, {"v", ToJsonVec(x.v)}}; }

json FullStateJson(const ImuState& x) {
  return {{"R", ToJson(x.R)},   {"q_wxyz", ToJsonVec(so3::ToQuaternionWxyz(x.R))},
          {"p", ToJsonVec(x.p)}, {"v", ToJsonVec(x.v)},
          {"bg", ToJsonVec(x.bg)}, {"ba", ToJsonVec(x.ba)}};
}

struct Case {
  std::vector<ImuSample> samples;
  std::vector<ImuSample> mid_samples;  // not used by the integrators; kept for clarity of the zoh/mid input
  Vec3 gravity;
  ImuNoise noise;
  ImuState x_s;
  Mat15 cov_s_left;
  Vec15 end_perturbation;
  Vec3 dbg, dba;
};

Case Parse(const json& c) {
  Case k;
  const json& imu = At(c, "imu", "");
  if (!imu.is_array() || imu.size() < 2) throw Error("/imu: expected at least two rows");
  k.samples.reserve(imu.size());
  for (std::size_t i = 0; i < imu.size(); ++i) {
    const std::string ptr = "/imu/" + std::to_string(i);
    const json& row = imu[i];
    if (!row.is_array() || row.size() != 7) throw Error(ptr + ": expected [t, wx, wy, wz, ax, ay, az]");
    ImuSample s;
    s.t = Number(row[0], ptr + "/0");
    for (int a = 0; a < 3; ++a) {
      s.gyro[a] = Number(row[1 + a], ptr + "/" + std::to_string(1 + a));
      s.accel[a] = Number(row[4 + a], ptr + "/" + std::to_string(4 + a));
    }
    if (!k.samples.empty() && !(s.t > k.samples.back().t)) throw Error(ptr + "/0: time does not increase");
    k.samples.push_back(s);
  }
  k.gravity = Vector3(At(c, "gravity", ""), "/gravity");
  const json& n = At(c, "noise", "");
  k.noise.gyro_noise_density = Number(At(n, "gyro_noise_density", "/noise"), "/noise/gyro_noise_density");
  k.noise.accel_noise_density = Number(At(n, "accel_noise_density", "/noise"), "/noise/accel_noise_density");
  k.noise.gyro_random_walk = Number(At(n, "gyro_random_walk", "/noise"), "/noise/gyro_random_walk");
  k.noise.accel_random_walk = Number(At(n, "accel_random_walk", "/noise"), "/noise/accel_random_walk");
  const json& s = At(c, "state_s", "");
  const json& q = At(s, "q_wxyz", "/state_s");
  if (!q.is_array() || q.size() != 4) throw Error("/state_s/q_wxyz: expected 4 numbers");
  k.x_s.R = so3::FromQuaternionWxyz(Number(q[0], "/state_s/q_wxyz/0"), Number(q[1], "/state_s/q_wxyz/1"),
                                    Number(q[2], "/state_s/q_wxyz/2"), Number(q[3], "/state_s/q_wxyz/3"));
  k.x_s.p = Vector3(At(s, "p", "/state_s"), "/state_s/p");
  k.x_s.v = Vector3(At(s, "v", "/state_s"), "/state_s/v");
  k.x_s.bg = Vector3(At(s, "bg", "/state_s"), "/state_s/bg");
  k.x_s.ba = Vector3(At(s, "ba", "/state_s"), "/state_s/ba");
  const json& cov = At(At(c, "cov_s_left", ""), "matrix", "/cov_s_left");
  if (!cov.is_array() || cov.size() != 15) throw Error("/cov_s_left/matrix: expected 15 rows");
  for (int i = 0; i < 15; ++i) {
    const std::string ptr = "/cov_s_left/matrix/" + std::to_string(i);
    if (!cov[i].is_array() || cov[i].size() != 15) throw Error(ptr + ": expected 15 numbers");
    for (int j = 0; j < 15; ++j) k.cov_s_left(i, j) = Number(cov[i][j], ptr + "/" + std::to_string(j));
  }
  const json& e = At(c, "end_perturbation", "");
  if (!e.is_array() || e.size() != 15) throw Error("/end_perturbation: expected 15 numbers");
  for (int i = 0; i < 15; ++i) k.end_perturbation[i] = Number(e[i], "/end_perturbation/" + std::to_string(i));
  const json& bd = At(c, "bias_delta", "");
  k.dbg = Vector3(At(bd, "bg", "/bias_delta"), "/bias_delta/bg");
  k.dba = Vector3(At(bd, "ba", "/bias_delta"), "/bias_delta/ba");
  return k;
}

// GTSAM's `mid` input: the mean of samples k and k+1 held over [t_k, t_k+1]. For the native
// zero-order-hold scheme this is fed as a new sample sequence with the same timestamps.
std::vector<ImuSample> MidSamples(const std::vector<ImuSample>& s) {
  std::vector<ImuSample> out(s);
  for (std::size_t k = 0; k + 1 < s.size(); ++k) {
    out[k].gyro = 0.5 * (s[k].gyro + s[k + 1].gyro);
    out[k].accel = 0.5 * (s[k].accel + s[k + 1].accel);
  }
  return out;
}

struct Method {
  std::string propagator;     // preintegration by propagation with this propagator, or
  std::string preintegrator;  // a native preintegrator
  std::string convention;     // increment convention of the slot
};

Preintegrated Measure(const Registry& reg, const Method& m, const SampleWindow& w, const Vec3& bg, const Vec3& ba,
                      const ImuNoise& noise) {
  if (!m.propagator.empty()) return PreintegrateByPropagation(reg, m.propagator, w, bg, ba, noise);
  return PreintegrateNative(reg, m.preintegrator, w, bg, ba, noise);
}

// GTSAM's 9-vector [theta, p, v] of an increment: Log(dR) (= the tangent vector for
// |theta| < pi), dp, dv.
Vec9 Xi(const PreintIncrement& d) {
  Vec9 xi;
  xi << so3::Log(d.dR), d.dp, d.dv;
  return xi;
}

json Slot(const Registry& reg, const Case& k, const Method& method, const SampleWindow& w, const char* variant) {
  const Preintegrated m = Measure(reg, method, w, k.x_s.bg, k.x_s.ba, k.noise);
  const PreintegratedIn in = Express(reg, m, method.convention);
  ImuNoise no_walk = k.noise;
  no_walk.gyro_random_walk = 0.0;
  no_walk.accel_random_walk = 0.0;
  const PreintegratedIn in9 = Express(reg, Measure(reg, method, w, k.x_s.bg, k.x_s.ba, no_walk), method.convention);

  json s;
  s["variant"] = variant;
  s["deltaT"] = m.dt;
  s["deltaR"] = ToJson(m.delta.dR);
  s["deltaP"] = ToJsonVec(m.delta.dp);
  s["deltaV"] = ToJsonVec(m.delta.dv);
  if (std::string(variant) == "tangent") s["preintegrated_tangent"] = ToJsonVec(Xi(m.delta));
  s["J_bias"] = ToJson(in.J_bias);
  s["cov15"] = ToJson(in.cov);
  s["cov9"] = ToJson(in9.cov.topLeftCorner<9, 9>());

  const ImuState pred = Predict(k.x_s, m.delta, m.dt, k.gravity);
  s["predict"] = NavJson(pred);

  // First-order bias correction in the chart of the slot's bias Jacobian, and re-integration.
  const Vec3 bg_new = k.x_s.bg + k.dbg, ba_new = k.x_s.ba + k.dba;
  const PreintIncrement corrected = BiasCorrectedDelta(reg, m, in.jacobian_convention, bg_new, ba_new);
  ImuState x_new = k.x_s;
  x_new.bg = bg_new;
  x_new.ba = ba_new;
  const Preintegrated m_new = Measure(reg, method, w, bg_new, ba_new, k.noise);
  s["bias_correction"] = {{"bg_new", ToJsonVec(bg_new)},
                          {"ba_new", ToJsonVec(ba_new)},
                          {"first_order_delta_xi", ToJsonVec(Xi(corrected))},
                          {"first_order_predict", NavJson(Predict(x_new, corrected, m.dt, k.gravity))},
                          {"reintegrated_predict", NavJson(Predict(x_new, m_new.delta, m_new.dt, k.gravity))}};

  // Factor: end state = prediction retracted in gtsam_navstate by [dtheta, dp, dv]; biases =
  // start biases + [dbg, dba]; Jacobians in the chart of GTSAM's ImuFactor variables.
  const auto navstate = reg.state_convention("gtsam_navstate");
  const BlockLabels nl = navstate->labels();
  Vec15 d = Vec15::Zero();
  d.segment<3>(BlockOffset(nl, "theta")) = k.end_perturbation.segment<3>(0);
  d.segment<3>(BlockOffset(nl, "p")) = k.end_perturbation.segment<3>(3);
  d.segment<3>(BlockOffset(nl, "v")) = k.end_perturbation.segment<3>(6);
  ImuState x_e;
  navstate->retract(pred, d, x_e);
  x_e.bg = k.x_s.bg + k.end_perturbation.segment<3>(9);
  x_e.ba = k.x_s.ba + k.end_perturbation.segment<3>(12);
  const Residual r = ComputeResidual(reg, ResidualKind::Gtsam, m, k.x_s, x_e, "gtsam_pose3_vel", k.gravity);
  const BlockLabels pl = reg.state_convention("gtsam_pose3_vel")->labels();
  const int th = BlockOffset(pl, "theta"), tt = BlockOffset(pl, "p"), vv = BlockOffset(pl, "v"),
            ba = BlockOffset(pl, "ba"), bg = BlockOffset(pl, "bg");
  auto pose_cols = [&](const Mat15& H) {
    Eigen::Matrix<double, 9, 6> out;
    out << H.block<9, 3>(0, th), H.block<9, 3>(0, tt);
    return out;
  };
  Eigen::Matrix<double, 9, 6> H_bias;
  H_bias << r.H_start.block<9, 3>(0, ba), r.H_start.block<9, 3>(0, bg);
  Eigen::Matrix<double, 6, 1> bias_err;
  bias_err << x_e.ba - k.x_s.ba, x_e.bg - k.x_s.bg;
  s["factor"] = {{"state_e", NavJson(x_e)},
                 {"bias_e", {{"bg", ToJsonVec(x_e.bg)}, {"ba", ToJsonVec(x_e.ba)}}},
                 {"error9", ToJsonVec(r.r.head<9>())},
                 {"bias_error6_bj_minus_bi", ToJsonVec(bias_err)},
                 {"H_pose_i", ToJson(pose_cols(r.H_start))},
                 {"H_vel_i", ToJson(r.H_start.block<9, 3>(0, vv))},
                 {"H_pose_j", ToJson(pose_cols(r.H_end))},
                 {"H_vel_j", ToJson(r.H_end.block<9, 3>(0, vv))},
                 {"H_bias_i", ToJson(H_bias)}};
  return s;
}

json PropagationBlock(const Registry& reg, const Case& k, const std::string& propagator, const SampleWindow& w) {
  PropagationInput in;
  in.x_s = k.x_s;
  in.cov_s = k.cov_s_left;
  in.noise = k.noise;
  in.gravity = k.gravity;
  in.window = w;
  const PropagationResult r = reg.propagate(propagator, "left", in);
  return {{"convention", "left"}, {"blocks", {"p", "theta", "v", "bg", "ba"}}, {"state_e", FullStateJson(r.x_e)},
          {"Phi", ToJson(r.Phi)},  {"cov", ToJson(r.cov)}};
}

}  // namespace

json Run(const Registry& reg, const json& case_json) {
  const Case k = Parse(case_json);
  SampleWindow zoh, mid_zoh;
  const std::vector<ImuSample> mid = MidSamples(k.samples);
  const double t_s = k.samples.front().t, t_e = k.samples.back().t;
  Status st = MakeWindow(k.samples.data(), k.samples.size(), t_s, t_e, zoh);
  if (!st.ok()) throw Error("/imu: " + st.message());
  st = MakeWindow(mid.data(), mid.size(), t_s, t_e, mid_zoh);
  if (!st.ok()) throw Error("/imu: " + st.message());

  json out;
  out["case_id"] = case_json.value("case_id", "");
  out["generator"] = "imuconv refcase";
  out["orders"] = {{"J_bias", "rows [theta,p,v] cols [ba,bg]"},
                   {"cov15", "[theta,p,v,ba,bg]"},
                   {"cov9", "[theta,p,v]"},
                   {"H_bias_i", "cols [ba,bg]"},
                   {"H_pose", "Pose3 local coords [rot,trans], Pose3 retract=Expmap"},
                   {"factor_error9", "[theta,p,v] = state_e.localCoordinates(predict)"}};
  out["zoh"]["manifold"] = Slot(reg, k, {"euler", "", "gtsam_manifold"}, zoh, "manifold");
  out["zoh"]["tangent"] = Slot(reg, k, {"", "tangent", "gtsam_tangent"}, zoh, "tangent");
  out["mid"]["manifold"] = Slot(reg, k, {"rk4", "", "gtsam_manifold"}, zoh, "manifold");
  out["mid"]["tangent"] = Slot(reg, k, {"rk4", "", "gtsam_tangent"}, zoh, "tangent");
  // The exact-discretisation counterparts of GTSAM's `mid` slots: the same schemes fed the
  // averaged input (midpoint integrator; native tangent on averaged samples).
  out["mid_exact"]["manifold"] = Slot(reg, k, {"midpoint", "", "gtsam_manifold"}, zoh, "manifold");
  out["mid_exact"]["tangent"] = Slot(reg, k, {"", "tangent", "gtsam_tangent"}, mid_zoh, "tangent");

  for (const char* p : {"euler", "midpoint", "rk4"}) out["propagation"][p] = PropagationBlock(reg, k, p, zoh);
  // Propagation by preintegration of the zoh.manifold measurement (paper, section 3.2).
  const Preintegrated m = PreintegrateByPropagation(reg, "euler", zoh, k.x_s.bg, k.x_s.ba, k.noise);
  const PropagationResult r = PropagateByPreintegration(reg, m, k.x_s, k.cov_s_left, "left", k.gravity);
  out["propagation"]["by_preintegration_zoh_manifold"] = {{"convention", "left"},
                                                          {"blocks", {"p", "theta", "v", "bg", "ba"}},
                                                          {"state_e", FullStateJson(r.x_e)},
                                                          {"Phi", ToJson(r.Phi)},
                                                          {"cov", ToJson(r.cov)}};
  return out;
}

}  // namespace imuconv::refcase
