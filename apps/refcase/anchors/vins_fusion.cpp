// refcase --anchor vins-fusion: see anchor.h for what the fields are.
#include <Eigen/Geometry>
#include <cmath>
#include <utility>

#include "anchor_writer.h"
#include "imuconv/kernels/vins_fusion.h"
#include "imuconv/kernels/vins_fusion_residual.h"

namespace imuconv::refcase {
namespace {

using json = nlohmann::json;
using namespace imuconv::kernels;
using namespace anchor_support;

json VinsStateJson(const VinsFusionFactorState& x) {
  return {{"Q_wxyz", Wxyz(x.Q)},
          {"R", ToJson(x.Q.toRotationMatrix())},
          IMUCONV_ANCHOR_MEMBERS(FieldJson, x, (P)(V)(Ba)(Bg))};
}

json VinsOutputJson(const VinsFusionFactorOutput& o) {
  return {IMUCONV_ANCHOR_MEMBERS(
      FieldJson, o,
      (residual)(jacobian_pose_i)(jacobian_speedbias_i)(jacobian_pose_j)(jacobian_speedbias_j))};
}

json VinsIntegrationJson(const VinsFusionPreintegration& r) {
  return {{"delta_q_wxyz", Wxyz(r.delta_q)},
          IMUCONV_ANCHOR_MEMBERS(FieldJson, r, (sum_dt)(delta_p)(delta_v)(jacobian)(covariance))};
}

json VinsFusion(const Registry&, const Case& k) {
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
  i.Q = StartQuaternion(k);
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

}  // namespace
}  // namespace imuconv::refcase

IMUCONV_ANCHOR_WRITER(vins_fusion, "vins-fusion", &VinsFusion)
