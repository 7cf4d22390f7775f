// refcase --anchor openvins: see anchor.h for what the fields are.
#include <Eigen/Geometry>
#include <cmath>
#include <utility>

#include "anchor_writer.h"

namespace imuconv::refcase {
namespace {

using json = nlohmann::json;
using namespace anchor_support;

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
}  // namespace imuconv::refcase

IMUCONV_ANCHOR_WRITER(openvins, "openvins", &OpenVins)
