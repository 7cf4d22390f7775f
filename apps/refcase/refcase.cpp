#include "refcase.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include "imuconv/bridge.h"
#include "imuconv/numeric.h"
#include "imuconv/pipeline/matrix_rows.h"
#include "imuconv/pipeline/timing.h"
#include "imuconv/printable.h"
#include "imuconv/so3.h"

namespace imuconv::refcase {
namespace {

using json = nlohmann::json;

// Every input is checked by the rules `imuconv run` applies to its own inputs, and every
// error names the JSON pointer (the command line adds the file): nothing is repaired or taken
// as a default in silence.

/// RFC 6901 token of a key, made printable for a message.
std::string Token(const std::string& key) {
  std::string t;
  for (char c : key)
    t += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  return Printable(t);
}

std::string Num(double v) {
  std::ostringstream o;
  o.precision(10);
  o << v;
  return o.str();
}

/// The object at `ptr`, with no key outside `keys` (a misspelt optional key would otherwise
/// be ignored).
const json& Object(const json& j, const std::string& ptr, std::initializer_list<const char*> keys) {
  if (!j.is_object())
    throw Error((ptr.empty() ? std::string("the document") : ptr) + ": expected a JSON object");
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (std::none_of(keys.begin(), keys.end(), [&](const char* k) { return it.key() == k; })) {
      std::string known;
      for (const char* k : keys) known += std::string(known.empty() ? "" : ", ") + k;
      throw Error(ptr + "/" + Token(it.key()) + ": unknown key; expected one of " + known);
    }
  }
  return j;
}

const json& At(const json& j, const std::string& key, const std::string& ptr) {
  if (!j.contains(key)) throw Error(ptr + "/" + key + ": missing");
  return j.at(key);
}

double Number(const json& j, const std::string& ptr) {
  if (!j.is_number()) throw Error(ptr + ": expected a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw Error(ptr + ": expected a finite number");
  return v;
}

double NonNegative(const json& j, const std::string& ptr) {
  const double v = Number(j, ptr);
  if (v < 0.0) throw Error(ptr + ": expected a non-negative number, found " + Num(v));
  return v;
}

Vec3 Vector3(const json& j, const std::string& ptr) {
  if (!j.is_array() || j.size() != 3) throw Error(ptr + ": expected an array of 3 numbers");
  return Vec3(Number(j[0], ptr + "/0"), Number(j[1], ptr + "/1"), Number(j[2], ptr + "/2"));
}

/// An array of strings that, when present, must be exactly `expected` (the layout the runner
/// assumes: a case written for another column or block order must not be read as this one).
void FixedLabels(const json& parent, const char* key, const std::string& ptr,
                 const std::vector<std::string>& expected) {
  if (!parent.contains(key)) return;
  const json& j = parent.at(key);
  std::string want;
  for (const auto& e : expected) want += std::string(want.empty() ? "[" : ", ") + "\"" + e + "\"";
  want += "]";
  bool same = j.is_array() && j.size() == expected.size();
  for (std::size_t i = 0; same && i < expected.size(); ++i)
    same = j[i].is_string() && j[i].get<std::string>() == expected[i];
  if (!same)
    throw Error(ptr + "/" + key + ": expected " + want +
                " (the only layout imuconv refcase reads)");
}

/// Same rule and tolerance as `imuconv run` (StateFromJson): a unit quaternion within 1e-6,
/// never an all-zero one taken as the identity or a scaled one normalised in silence.
Mat3 Rotation(const json& q, const std::string& ptr) {
  if (!q.is_array() || q.size() != 4)
    throw Error(ptr + ": expected a quaternion [w, x, y, z] (4 numbers)");
  Eigen::Vector4d v;
  for (int i = 0; i < 4; ++i)
    v[i] = Number(q[static_cast<std::size_t>(i)], ptr + "/" + std::to_string(i));
  const double norm = v.norm();
  if (!(std::abs(norm - 1.0) <= 1e-6))
    throw Error(
        ptr +
        ": expected a unit quaternion [w, x, y, z] (norm within 1e-6 of 1), found one of norm " +
        Num(norm));
  return so3::FromQuaternionWxyz(v[0], v[1], v[2], v[3]);
}

/// Same rule as `imuconv run`: imuconv::CovarianceProblem with kCovarianceTol (1e-9 on the
/// correlation scale: round-off passes, a real defect does not); nothing is repaired.
void CheckCovariance(const Mat15& C, const std::string& ptr) {
  std::string p = CovarianceProblem(C, kCovarianceTol);
  if (p.empty()) return;
  if (p.find("eigenvalue") == std::string::npos && C.allFinite()) {
    const Mat15 sym = 0.5 * (C + C.transpose());
    const Eigen::SelfAdjointEigenSolver<Mat15> eig(sym, Eigen::EigenvaluesOnly);
    p += " (smallest eigenvalue of (C + C^T)/2: " + Num(eig.eigenvalues().minCoeff()) + ")";
  }
  throw Error(ptr + ": not a valid covariance: " + p + "; nothing is repaired, fix the input");
}

}  // namespace

std::vector<ImuSample> MidSampleInput(const std::vector<ImuSample>& samples) {
  std::vector<ImuSample> out(samples);
  for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
    out[k].gyro = 0.5 * (samples[k].gyro + samples[k + 1].gyro);
    out[k].accel = 0.5 * (samples[k].accel + samples[k + 1].accel);
  }
  return out;
}

json ToJson(const Eigen::MatrixXd& m) { return pipeline::MatrixToJson(m); }

json ToJsonVec(const Eigen::VectorXd& v) {
  json a = json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v[i]);
  return a;
}

namespace {

json NavJson(const ImuState& x) {
  return {{"R", ToJson(x.R)}, {"p", ToJsonVec(x.p)}, {"v", ToJsonVec(x.v)}};
}

json FullStateJson(const ImuState& x) {
  return {{"R", ToJson(x.R)},      {"q_wxyz", ToJsonVec(so3::ToQuaternionWxyz(x.R))},
          {"p", ToJsonVec(x.p)},   {"v", ToJsonVec(x.v)},
          {"bg", ToJsonVec(x.bg)}, {"ba", ToJsonVec(x.ba)}};
}

/// The timing rules of `imuconv run`, by the pipeline's own check (FindTimingIssue with the
/// default policy): the median period must give a plausible IMU rate, 1 Hz to 100 kHz (else
/// the times are not in seconds), and no gap may exceed 10 x the median period (the
/// generator's jitter stays within 1.4 x). Either would otherwise be integrated across in
/// silence. The advice is refcase's own: a case has no time_unit or allow_gaps to set.
void CheckTiming(const std::vector<ImuSample>& s) {
  std::vector<double> t(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) t[i] = s[i].t;
  const pipeline::TimingPolicy policy;
  const auto issue =
      pipeline::FindTimingIssue(t, policy, pipeline::TimeUnit::s, pipeline::TimeSource::imu);
  if (!issue) return;
  const double median = issue->median_period;
  if (issue->kind == pipeline::TimingIssue::Kind::rate)
    throw Error("/imu: the median period is " + Num(median) + " s (rate " + Num(1.0 / median) +
                " Hz); an IMU rate is expected between " + Num(pipeline::kMinRateHz) + " Hz and " +
                Num(pipeline::kMaxRateHz / 1000) + " kHz: t must be in seconds (FORMAT.md)");
  throw Error("/imu/" + std::to_string(issue->index) + "/0: gap of " + Num(issue->gap) +
              " s before this sample (the median period is " + Num(median) + " s; limit " +
              Num(policy.max_gap_factor) + " x median = " + Num(issue->limit) +
              " s): a reference case must be sampled without gaps");
}

}  // namespace

Case ParseCase(const json& c) {
  Case k;
  Object(c, "",
         {"case_id", "kind", "gravity", "noise", "imu_columns", "imu", "state_s", "cov_s_left",
          "end_perturbation", "bias_delta"});
  for (const char* key : {"case_id", "kind"})
    if (c.contains(key) && !c.at(key).is_string())
      throw Error(std::string("/") + key + ": expected a string");
  FixedLabels(c, "imu_columns", "", {"t", "wx", "wy", "wz", "ax", "ay", "az"});
  const json& imu = At(c, "imu", "");
  if (!imu.is_array() || imu.size() < 2)
    throw Error("/imu: expected an array of at least two rows [t, wx, wy, wz, ax, ay, az]");
  k.samples.reserve(imu.size());
  for (std::size_t i = 0; i < imu.size(); ++i) {
    const std::string ptr = "/imu/" + std::to_string(i);
    const json& row = imu[i];
    if (!row.is_array() || row.size() != 7)
      throw Error(ptr + ": expected [t, wx, wy, wz, ax, ay, az]");
    ImuSample s;
    s.t = Number(row[0], ptr + "/0");
    for (int a = 0; a < 3; ++a) {
      s.gyro[a] = Number(row[1 + a], ptr + "/" + std::to_string(1 + a));
      s.accel[a] = Number(row[4 + a], ptr + "/" + std::to_string(4 + a));
    }
    if (!k.samples.empty() && !(s.t > k.samples.back().t))
      throw Error(ptr + "/0: time " + Num(s.t) +
                  " s does not increase (the previous sample is at " + Num(k.samples.back().t) +
                  " s)");
    k.samples.push_back(s);
  }
  CheckTiming(k.samples);
  k.gravity = Vector3(At(c, "gravity", ""), "/gravity");
  const json& n = Object(
      At(c, "noise", ""), "/noise",
      {"gyro_noise_density", "accel_noise_density", "gyro_random_walk", "accel_random_walk"});
  k.noise.gyro_noise_density =
      NonNegative(At(n, "gyro_noise_density", "/noise"), "/noise/gyro_noise_density");
  k.noise.accel_noise_density =
      NonNegative(At(n, "accel_noise_density", "/noise"), "/noise/accel_noise_density");
  k.noise.gyro_random_walk =
      NonNegative(At(n, "gyro_random_walk", "/noise"), "/noise/gyro_random_walk");
  k.noise.accel_random_walk =
      NonNegative(At(n, "accel_random_walk", "/noise"), "/noise/accel_random_walk");
  const json& s = Object(At(c, "state_s", ""), "/state_s", {"p", "q_wxyz", "v", "bg", "ba"});
  k.x_s.R = Rotation(At(s, "q_wxyz", "/state_s"), "/state_s/q_wxyz");
  for (std::size_t i = 0; i < 4; ++i)
    k.q_s_wxyz[static_cast<Eigen::Index>(i)] = s.at("q_wxyz").at(i).get<double>();
  k.x_s.p = Vector3(At(s, "p", "/state_s"), "/state_s/p");
  k.x_s.v = Vector3(At(s, "v", "/state_s"), "/state_s/v");
  k.x_s.bg = Vector3(At(s, "bg", "/state_s"), "/state_s/bg");
  k.x_s.ba = Vector3(At(s, "ba", "/state_s"), "/state_s/ba");
  const json& cs =
      Object(At(c, "cov_s_left", ""), "/cov_s_left", {"order", "definition", "matrix"});
  FixedLabels(cs, "order", "/cov_s_left", {"p", "theta", "v", "bg", "ba"});
  if (cs.contains("definition") && !cs.at("definition").is_string())
    throw Error("/cov_s_left/definition: expected a string");
  const json& cov = At(cs, "matrix", "/cov_s_left");
  if (!cov.is_array() || cov.size() != 15) throw Error("/cov_s_left/matrix: expected 15 rows");
  for (int i = 0; i < 15; ++i) {
    const std::string ptr = "/cov_s_left/matrix/" + std::to_string(i);
    if (!cov[i].is_array() || cov[i].size() != 15) throw Error(ptr + ": expected 15 numbers");
    for (int j = 0; j < 15; ++j)
      k.cov_s_left(i, j) = Number(cov[i][j], ptr + "/" + std::to_string(j));
  }
  CheckCovariance(k.cov_s_left, "/cov_s_left/matrix");
  const json& e = At(c, "end_perturbation", "");
  if (!e.is_array() || e.size() != 15) throw Error("/end_perturbation: expected 15 numbers");
  for (int i = 0; i < 15; ++i)
    k.end_perturbation[i] = Number(e[i], "/end_perturbation/" + std::to_string(i));
  const json& bd = Object(At(c, "bias_delta", ""), "/bias_delta", {"bg", "ba"});
  k.dbg = Vector3(At(bd, "bg", "/bias_delta"), "/bias_delta/bg");
  k.dba = Vector3(At(bd, "ba", "/bias_delta"), "/bias_delta/ba");
  return k;
}

/// One policy with `imuconv run`: JSON holds no NaN or infinity, and a variance computed from
/// valid inputs is never negative beyond round-off. Either is refused, naming the output
/// pointer, rather than written (as null, or as a "covariance" that is not one).
void CheckResults(const json& j, const std::string& ptr) {
  if (j.is_number_float() && !std::isfinite(j.get<double>()))
    throw Error("produced a non-finite number (output " + ptr + "); no output is written");
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      CheckResults(it.value(), ptr + "/" + Token(it.key()));
    for (const char* key : {"cov15", "cov9", "cov", "covariance", "Qd_summed"}) {
      if (!j.contains(key)) continue;
      const json& m = j.at(key);
      if (!m.is_array() || !std::all_of(m.begin(), m.end(), [&](const json& r) {
            return r.is_array() && r.size() == m.size();
          }))
        continue;  // "orders" names them with strings
      // J S J^T and Phi P Phi^T + Q of a positive semi-definite S or P have non-negative
      // variances up to round-off, far below 1e-9 of the largest variance.
      double scale = 0.0;
      for (std::size_t i = 0; i < m.size(); ++i)
        scale = std::max(scale, std::abs(m[i][i].get<double>()));
      for (std::size_t i = 0; i < m.size(); ++i)
        if (m[i][i].get<double>() < -kCovarianceTol * scale)
          throw Error("computed a covariance with a negative variance, entry (" +
                      std::to_string(i) + ", " + std::to_string(i) +
                      ") = " + Num(m[i][i].get<double>()) + " (output " + ptr + "/" + key +
                      "; tolerance 1e-9 of the largest variance " + Num(scale) +
                      "). The inputs were checked, so this is a defect of imuconv or of a plugin: "
                      "please report it. "
                      "No output is written");
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) CheckResults(j[i], ptr + "/" + std::to_string(i));
  }
}

namespace {

struct Method {
  std::string propagator;     // preintegration by propagation with this propagator, or
  std::string preintegrator;  // a native preintegrator
  std::string convention;     // increment convention of the slot
};

Preintegrated Measure(const Registry& reg, const Method& m, const SampleWindow& w, const Vec3& bg,
                      const Vec3& ba, const ImuNoise& noise) {
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

json Slot(const Registry& reg, const Case& k, const Method& method, const SampleWindow& w,
          const char* variant) {
  const Preintegrated m = Measure(reg, method, w, k.x_s.bg, k.x_s.ba, k.noise);
  const Preintegrated in = Express(reg, m, method.convention);
  ImuNoise no_walk = k.noise;
  no_walk.gyro_random_walk = 0.0;
  no_walk.accel_random_walk = 0.0;
  const Preintegrated in9 =
      Express(reg, Measure(reg, method, w, k.x_s.bg, k.x_s.ba, no_walk), method.convention);

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
  const PreintIncrement corrected =
      BiasCorrectedDelta(reg, m, in.jacobian_convention, bg_new, ba_new);
  ImuState x_new = k.x_s;
  x_new.bg = bg_new;
  x_new.ba = ba_new;
  const Preintegrated m_new = Measure(reg, method, w, bg_new, ba_new, k.noise);
  s["bias_correction"] = {
      {"bg_new", ToJsonVec(bg_new)},
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
  const Residual r =
      ComputeResidual(reg, ResidualKind::Gtsam, m, k.x_s, x_e, "gtsam_pose3_vel", k.gravity);
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

json PropagationBlock(const Registry& reg, const Case& k, const std::string& propagator,
                      const SampleWindow& w) {
  const PropagationResult r =
      reg.propagate(propagator, "left", {k.x_s, k.cov_s_left, k.noise, k.gravity, w});
  return {{"convention", "left"},
          {"blocks", {"p", "theta", "v", "bg", "ba"}},
          {"state_e", FullStateJson(r.x_e)},
          {"Phi", ToJson(r.Phi)},
          {"cov", ToJson(r.cov)}};
}

}  // namespace

json Run(const Registry& reg, const json& case_json) {
  const Case k = ParseCase(case_json, CaseKeys::all_required);  // every missing key named at once
  SampleWindow zoh, mid_zoh;
  const std::vector<ImuSample> mid = MidSampleInput(k.samples);
  const double t_s = k.samples.front().t, t_e = k.samples.back().t;
  Status st = MakeWindow(k.samples.data(), k.samples.size(), t_s, t_e, zoh);
  if (!st.ok()) throw Error("/imu: " + st.message());
  st = MakeWindow(mid.data(), mid.size(), t_s, t_e, mid_zoh);
  if (!st.ok()) throw Error("/imu: " + st.message());

  json out;
  out["case_id"] = case_json.contains("case_id") ? case_json.at("case_id") : json("");
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

  for (const char* p : {"euler", "midpoint", "rk4"})
    out["propagation"][p] = PropagationBlock(reg, k, p, zoh);
  // Propagation by preintegration of the zoh.manifold measurement (paper, section 3.2).
  const Preintegrated m = PreintegrateByPropagation(reg, "euler", zoh, k.x_s.bg, k.x_s.ba, k.noise);
  const PropagationResult r =
      PropagateByPreintegration(reg, m, k.x_s, k.cov_s_left, "left", k.gravity);
  out["propagation"]["by_preintegration_zoh_manifold"] = {
      {"convention", "left"},
      {"blocks", {"p", "theta", "v", "bg", "ba"}},
      {"state_e", FullStateJson(r.x_e)},
      {"Phi", ToJson(r.Phi)},
      {"cov", ToJson(r.cov)}};
  CheckResults(out, "");
  return out;
}

}  // namespace imuconv::refcase
