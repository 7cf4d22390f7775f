// refcase --anchor orb-slam3: ORB-SLAM3's fields of tests/data/reference/anchors/orb-slam3/
// (README.md there): IMU::Preintegrated fed as Tracking::PreintegrateIMU feeds it, the
// tracking prediction in float, the same relation in double, EdgeInertial at the linearization
// bias and at the new bias, the first-order bias update and Reintegrate. Single precision where
// ORB-SLAM3 computes in it (the kernel, imuconv/kernels/orb_slam3.h); the floats are written
// widened to double, as the anchor files hold them.
#include <Eigen/Geometry>
#include <vector>

#include "anchor_writer.h"
#include "imuconv/kernels/orb_slam3.h"

namespace imuconv::refcase {
namespace {

using json = nlohmann::json;
using namespace imuconv::kernels;
using namespace anchor_support;

/// IMU.Frequency of the anchors: the cases' nominal rate (the `orb_slam3` plugin takes it from
/// the window's median step, which gives 200 on every reference case).
constexpr double kOrbSlam3ImuFrequency = 200.0;

template <typename Derived>
json OrbFloatJson(const Eigen::MatrixBase<Derived>& m) {
  if constexpr (Derived::ColsAtCompileTime == 1)
    return ToJsonVec(m.template cast<double>());
  else
    return ToJson(m.template cast<double>());
}

json OrbPreintegratedJson(const OrbSlam3Preintegrated& p) {
  return {{"dT", static_cast<double>(p.dT)},
          IMUCONV_ANCHOR_MEMBERS(OrbFloatJson, p, (dR)(dV)(dP)(JRg)(JVg)(JVa)(JPg)(JPa)(avgA)(avgW))
          {"C",
           {{"order", json::array({"theta", "v", "p", "bg", "ba"})},
            {"definition",
             "dR = dR^ Exp(dtheta) (right, frame of the first sample), dV = dV^ + dv, dP = dP^ + "
             "dp, bg = bg^ + dbg, ba = ba^ + dba; bias blocks are only the accumulated random walk "
             "(no cross terms)"},
            {"matrix", OrbFloatJson(p.C)}}}};
}

/// A vertex's values as the file writes them: R, p, v, biases and R's quaternion as Eigen's
/// Quaterniond(R) converts it (the sign its branch on the trace and the largest diagonal entry
/// gives: w < 0 on jitter-1 and smooth-3), the conversion ORB-SLAM3's Converter and g2o use.
json OrbStateJson(const OrbSlam3Pose<double>& x, const Vec3& bg, const Vec3& ba) {
  return {{"R", ToJson(x.R)},    {"q_wxyz", Wxyz(Eigen::Quaterniond(x.R))},
          {"p", ToJsonVec(x.p)}, {"v", ToJsonVec(x.v)},
          {"bg", ToJsonVec(bg)}, {"ba", ToJsonVec(ba)}};
}

json OrbEdgeJson(const OrbSlam3EdgeInertial& e) {
  return {IMUCONV_ANCHOR_MEMBERS(
      FieldJson, e,
      (residual)(chi2)(J_pose1)(J_vel1)(J_gyro_bias1)(J_acc_bias1)(J_pose2)(J_vel2))};
}

json OrbSlam3Fields(const Registry&, const Case& k) {
  std::vector<OrbSlam3Step> steps;
  Require(OrbSlam3Steps(k.samples, steps), "ORB-SLAM3 preintegration");
  const OrbSlam3Calib calib = OrbSlam3CalibFromDensities(k.noise, kOrbSlam3ImuFrequency);
  // IMU::Bias holds the linearization point in float.
  const OrbSlam3Bias b_lin{k.x_s.bg.cast<float>(), k.x_s.ba.cast<float>()};
  const OrbSlam3Preintegrated pre = PreintegrateOrbSlam3(steps, calib, b_lin);

  json out;
  out["preintegration"] = OrbPreintegratedJson(pre);

  // The start state from the case's quaternion as written (ORB-SLAM3's frames hold it so).
  OrbSlam3Pose<double> s1;
  s1.R = StartQuaternion(k).toRotationMatrix();
  s1.p = k.x_s.p;
  s1.v = k.x_s.v;
  OrbSlam3Pose<float> s1_float;
  s1_float.R = s1.R.cast<float>();
  s1_float.p = s1.p.cast<float>();
  s1_float.v = s1.v.cast<float>();
  const OrbSlam3Pose<float> tracked = PredictOrbSlam3Tracking(pre, s1_float);
  out["predict_tracking_float"] = {{"R", OrbFloatJson(tracked.R)},
                                   {"p", OrbFloatJson(tracked.p)},
                                   {"v", OrbFloatJson(tracked.v)}};
  const OrbSlam3Pose<double> pred = PredictOrbSlam3(pre, s1);
  out["predict"] = OrbStateJson(pred, k.x_s.bg, k.x_s.ba);

  // End state: the shared recipe on `predict`, end_perturbation = [dth, dp, dv, dbg, dba].
  const Vec15& e = k.end_perturbation;
  OrbSlam3Pose<double> s2;
  s2.R = pred.R * so3::Exp(e.segment<3>(0));
  s2.p = pred.p + pred.R * e.segment<3>(3);
  s2.v = pred.v + pred.R * e.segment<3>(6);
  const Vec3 bg_new = k.x_s.bg + k.dbg, ba_new = k.x_s.ba + k.dba;
  out["edge_inertial"] = {
      {"g", json::array({0.0, 0.0, -static_cast<double>(9.81f)})},  // IMU::GRAVITY_VALUE
      {"dt", static_cast<double>(pre.dT)},
      {"information", ToJson(OrbSlam3EdgeInformation(pre))},
      {"state_i", OrbStateJson(s1, k.x_s.bg, k.x_s.ba)},
      {"state_j", OrbStateJson(s2, k.x_s.bg + e.segment<3>(9), k.x_s.ba + e.segment<3>(12))},
      {"residual_at_predict",
       ToJsonVec(EvaluateOrbSlam3EdgeInertial(pre, s1, k.x_s.bg, k.x_s.ba, pred).residual)},
      {"at_lin_bias", OrbEdgeJson(EvaluateOrbSlam3EdgeInertial(pre, s1, k.x_s.bg, k.x_s.ba, s2))},
      {"state_i_new_bias", OrbStateJson(s1, bg_new, ba_new)},
      {"at_new_bias", OrbEdgeJson(EvaluateOrbSlam3EdgeInertial(pre, s1, bg_new, ba_new, s2))}};

  const OrbSlam3Bias b_new{bg_new.cast<float>(), ba_new.cast<float>()};
  Eigen::Matrix<float, 6, 1> db;
  db << b_new.bg - pre.b.bg, b_new.ba - pre.b.ba;
  out["bias_correction"] = {
      {"bg_new", ToJsonVec(bg_new)},
      {"ba_new", ToJsonVec(ba_new)},
      {"bias_new_float", {{"bg", OrbFloatJson(b_new.bg)}, {"ba", OrbFloatJson(b_new.ba)}}},
      {"first_order",
       {{"dR", OrbFloatJson(OrbSlam3DeltaRotation(pre, b_new))},
        {"dV", OrbFloatJson(OrbSlam3DeltaVelocity(pre, b_new))},
        {"dP", OrbFloatJson(OrbSlam3DeltaPosition(pre, b_new))},
        {"db", OrbFloatJson(db)},
        // SetNewBias then GetUpdatedDelta* is GetDelta*(b_new): the kernel has one function
        // for both (OrbSlam3Delta*), as upstream's two compute the same expressions.
        {"equals_GetDelta_of_new_bias", true}}},
      {"reintegrated", OrbPreintegratedJson(PreintegrateOrbSlam3(pre.steps, calib, b_new))}};
  return out;
}

}  // namespace
}  // namespace imuconv::refcase

IMUCONV_ANCHOR_WRITER(orb_slam3, "orb-slam3", &OrbSlam3Fields)
