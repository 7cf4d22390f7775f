// refcase --anchor okvis2: OKVIS2's ImuError (okvis_ceres, ethz-mrl/okvis2) on a case, with
// the anchors' inputs (tests/data/reference/anchors/README.md, okvis2/): the case's densities
// as sigma_*_c, g = -gravity_z (OKVIS's gravity is along the world's -z), a_max and g_max of
// config/euroc.yaml, every sample stamped as okvis::Time, t_start and t_end the first and last
// sample. `propagation` from state_s; `imu_error` evaluated at the linearization bias, at the
// new bias (first order: OKVIS re-integrates only intervals of fewer than 50 samples) and,
// `repropagated`, by a fresh ImuError integrated at the new bias. `raw` is
// EvaluateWithMinimalJacobians before weighting; `whitened` is S times `raw` with S formed as
// OKVIS forms it from an eigen-decomposition of P_delta: S's rows are principal directions
// whose signs (and, where eigenvalues nearly coincide, whose basis) are the solver's choice,
// so they match OKVIS's only up to those; S^T S = information does not depend on them.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "anchor_writer.h"
#include "imuconv/kernels/okvis2.h"

namespace imuconv::refcase {
namespace {

using json = nlohmann::json;
using namespace imuconv::kernels;
using namespace anchor_support;

const char* const kStateDefinition =
    "r = r^ + dr (world), C_WS = Exp(dalpha) C_WS^ (LEFT, world frame; PoseManifold::plus), v = v^ "
    "+ dv (world), bg = bg^ + dbg, ba = ba^ + dba";
const char* const kIncrementDefinition =
    "increments in the frame S0 of the first state: Delta_p = Delta_p^ + dp, Delta_C = "
    "Exp(dalpha) Delta_C^ (LEFT), Delta_v = Delta_v^ + dv, bg = bg^ + dbg, ba = ba^ + dba";

json Okvis2StateJson(const Okvis2State& s) {
  return {{"q_wxyz", Wxyz(s.q)},
          {"C", ToJson(s.q.normalized().toRotationMatrix())},
          IMUCONV_ANCHOR_MEMBERS(FieldJson, s, (r)(v)(bg)(ba))};
}

json Ordered(const char* const (&order)[5], const std::string& definition, const Mat15& m) {
  return {{"order", json::array({order[0], order[1], order[2], order[3], order[4]})},
          {"definition", definition},
          {"matrix", ToJson(m)}};
}

/// A square root S of the information, S^T S = information, as OKVIS forms it: D^1/2 V^T
/// with V the eigenvectors of P_delta (rows in the order its eigenvalues ascend) and D the
/// information in that basis, v_i^T information v_i (the inverse eigenvalue, or OKVIS's floor
/// where the kernel applied it).
Mat15 SquareRootInformation(const Okvis2Preintegration& p) {
  const Eigen::SelfAdjointEigenSolver<Mat15> eig(p.P_delta);
  Mat15 S;
  for (int i = 0; i < 15; ++i) {
    const Vec15 v = eig.eigenvectors().col(i);
    S.row(i) = std::sqrt(std::max(0.0, v.dot(p.information * v))) * v.transpose();
  }
  return S;
}

/// The residual and Jacobians of `t`, each as `of` gives it (the field itself, or S times it).
template <typename Of>
json TermsJson(const Okvis2ImuErrorTerms& t, const Of& of) {
  const auto field = [&of](const auto& m) { return FieldJson(of(m)); };
  return {IMUCONV_ANCHOR_MEMBERS(field, t,
                                 (residual)(jacobian_pose_0)(jacobian_speedbias_0)(jacobian_pose_1)(
                                     jacobian_speedbias_1)(jacobian_pose_0_minimal)(
                                     jacobian_pose_1_minimal))};
}

/// `raw` as EvaluateWithMinimalJacobians returns it before weighting, and `whitened`: S times
/// each of its fields.
json EvaluationJson(const Okvis2ImuErrorTerms& raw, const Mat15& S) {
  const auto itself = [](const auto& m) -> const auto& { return m; };
  const auto whitened = [&S](const auto& m) { return (S * m).eval(); };
  return {{"whitened", TermsJson(raw, whitened)}, {"raw", TermsJson(raw, itself)}};
}

json PreintegrationJson(const Okvis2Preintegration& p, const Vec3& v_ref, const Mat15& S) {
  static const char* const kOrder[5] = {"p", "alpha", "v", "bg", "ba"};
  Vec9 ref;
  ref << v_ref, p.bg_ref, p.ba_ref;
  return {{"Delta_q_wxyz", Wxyz(p.Delta_q)},
          {"Delta_R", ToJson(p.Delta_q.toRotationMatrix())},
          IMUCONV_ANCHOR_MEMBERS(FieldJson, p,
                                 (C_integral)(C_doubleintegral)(acc_integral)(acc_doubleintegral)(
                                     dalpha_db_g)(dv_db_g)(dp_db_g)(information))
          {"speedAndBiases_ref", ToJsonVec(ref)},
          {"redoCounter", 1},  // each ImuError below integrates once
          {"P_delta", Ordered(kOrder, kIncrementDefinition, p.P_delta)},
          {"squareRootInformation", ToJson(S)}};
}

json Okvis2(const Registry&, const Case& k) {
  if (k.gravity.x() != 0.0 || k.gravity.y() != 0.0)
    throw Error(
        "/gravity: OKVIS2's gravity is (0, 0, -g) in its world frame; this case's has x or y "
        "components");
  Okvis2ImuParameters params;  // a_max, g_max: config/euroc.yaml's
  params.sigma_g_c = k.noise.gyro_noise_density;
  params.sigma_a_c = k.noise.accel_noise_density;
  params.sigma_gw_c = k.noise.gyro_random_walk;
  params.sigma_aw_c = k.noise.accel_random_walk;
  params.g = -k.gravity.z();

  std::vector<Okvis2Sample> samples(k.samples.size());
  for (std::size_t i = 0; i < k.samples.size(); ++i) {
    Require(Okvis2TimeFromSeconds(k.samples[i].t, samples[i].t_ns),
            ("/imu/" + std::to_string(i) + "/0").c_str());
    samples[i].gyro = k.samples[i].gyro;
    samples[i].accel = k.samples[i].accel;
  }
  const std::int64_t t0 = samples.front().t_ns, t1 = samples.back().t_ns;

  // state_s as OKVIS's state, its quaternion as the case writes it (StartQuaternion).
  Okvis2State s0 = Okvis2StateOf(k.x_s);
  s0.q = StartQuaternion(k);

  static const char* const kOrder[5] = {"r", "alpha", "v", "bg", "ba"};
  Okvis2Propagation prop;
  Require(PropagateOkvis2(samples, params, s0, t0, t1, prop), "OKVIS2 propagation");
  json out;
  out["propagation"] = {
      {"n_steps", prop.steps},
      {"state_end", Okvis2StateJson(prop.end)},
      {"covariance", Ordered(kOrder, kStateDefinition, prop.covariance)},
      {"jacobian", Ordered(kOrder, std::string("d state_end / d state_start; ") + kStateDefinition,
                           prop.jacobian)}};

  // End state: the anchors' recipe on OKVIS's own prediction, the rotation by a quaternion
  // product q^ (x) exp(dth).
  const Vec15& e = k.end_perturbation;
  const Mat3 C_end = prop.end.q.toRotationMatrix();
  Okvis2State s1 = prop.end;
  s1.q = prop.end.q * QuaternionExp(e.segment<3>(0));
  s1.r = prop.end.r + C_end * e.segment<3>(3);
  s1.v = prop.end.v + C_end * e.segment<3>(6);
  s1.bg = k.x_s.bg + e.segment<3>(9);
  s1.ba = k.x_s.ba + e.segment<3>(12);
  Okvis2State s0_new = s0;
  s0_new.bg = k.x_s.bg + k.dbg;
  s0_new.ba = k.x_s.ba + k.dba;

  const double Delta_t = Okvis2Seconds(t1 - t0);
  Okvis2Preintegration at_lin;
  Require(PreintegrateOkvis2(samples, params, s0.bg, s0.ba, t0, t1, at_lin),
          "OKVIS2 preintegration");
  const Mat15 S_lin = SquareRootInformation(at_lin);
  // At the new bias an ImuError that has integrated keeps its integration unless the interval
  // is short (Okvis2RedoesPreintegration); then it integrates a second time.
  const bool redo = Okvis2RedoesPreintegration(at_lin, s0_new.bg, samples.size());
  Okvis2Preintegration at_new_kept = at_lin;
  if (redo)
    Require(PreintegrateOkvis2(samples, params, s0_new.bg, s0_new.ba, t0, t1, at_new_kept),
            "OKVIS2 re-integration");
  Okvis2Preintegration fresh;
  Require(PreintegrateOkvis2(samples, params, s0_new.bg, s0_new.ba, t0, t1, fresh),
          "OKVIS2 re-integration");
  const Mat15 S_new = SquareRootInformation(fresh);

  out["imu_error"] = {
      {"state_0", Okvis2StateJson(s0)},
      {"state_1", Okvis2StateJson(s1)},
      {"at_lin_bias",
       EvaluationJson(EvaluateOkvis2ImuError(at_lin, params, Delta_t, s0, s1), S_lin)},
      {"preintegration", PreintegrationJson(at_lin, s0.v, S_lin)},
      {"residual_at_propagation",
       ToJsonVec(EvaluateOkvis2ImuError(at_lin, params, Delta_t, s0, prop.end).residual)},
      {"state_0_new_bias", Okvis2StateJson(s0_new)},
      {"at_new_bias",
       EvaluationJson(EvaluateOkvis2ImuError(at_new_kept, params, Delta_t, s0_new, s1),
                      redo ? SquareRootInformation(at_new_kept) : S_lin)},
      {"redoCounter_after_new_bias", redo ? 2 : 1},
      {"repropagated",
       {{"at_new_bias",
         EvaluationJson(EvaluateOkvis2ImuError(fresh, params, Delta_t, s0_new, s1), S_new)},
        {"preintegration", PreintegrationJson(fresh, s0_new.v, S_new)}}}};
  return out;
}

}  // namespace
}  // namespace imuconv::refcase

IMUCONV_ANCHOR_WRITER(okvis2, "okvis2", &Okvis2)
