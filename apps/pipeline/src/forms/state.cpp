// The state form, read and written (json_io.h, state.h).
#include "state.h"

#include "imuconv/pipeline/json_parse.h"
#include "imuconv/so3.h"
#include "input_checks.h"

namespace imuconv::pipeline {

json Vec3ToJson(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

json StateToJson(const ImuState& x) {
  const Eigen::Vector4d q = so3::ToQuaternionWxyz(x.R);
  return {{"p", Vec3ToJson(x.p)},
          {"q_wxyz", json::array({q[0], q[1], q[2], q[3]})},
          {"v", Vec3ToJson(x.v)},
          {"bg", Vec3ToJson(x.bg)},
          {"ba", Vec3ToJson(x.ba)}};
}

void WriteState(JsonWriter& w, const ImuState& x) {
  const auto put = [&w](const char* key, const auto& v) {
    w.key(key);
    w.vector(v);
  };
  w.begin_object();
  put("p", x.p);
  put("q_wxyz", so3::ToQuaternionWxyz(x.R));
  put("v", x.v);
  put("bg", x.bg);
  put("ba", x.ba);
  w.end_object();
}

void WriteBias(JsonWriter& w, const Vec3& bg, const Vec3& ba) {
  w.begin_object();
  w.key("bg");
  w.vector(bg);
  w.key("ba");
  w.vector(ba);
  w.end_object();
}

std::optional<ImuState> StateFromJson(const Node& n) {
  if (!n.expect_object({"p", "q_wxyz", "q_GtoI_xyzw", "v", "bg", "ba"})) return std::nullopt;
  const std::size_t before = n.checker().count();
  ImuState x;
  if (auto p = n.vec3("p", true)) x.p = *p;
  // The rotation as imuconv writes it (Hamilton, body to world) or as OpenVINS stores it (JPL,
  // global to IMU): one of the two, never both (neither silently wins).
  if (n.has("q_wxyz") && n.has("q_GtoI_xyzw")) {
    n.checker().error(n.child_pointer("q_GtoI_xyzw"),
                      "give either q_wxyz or q_GtoI_xyzw, not both");
  } else if (auto jn = n.get("q_GtoI_xyzw", false)) {
    if (auto R = RotationFromJplQuaternion(*jn)) x.R = *R;
  } else if (!n.has("q_wxyz")) {
    n.checker().error(n.child_pointer("q_wxyz"),
                      "required key is missing (the body-to-world Hamilton q_wxyz, or OpenVINS's "
                      "JPL q_GtoI_xyzw)");
  } else if (auto qn = n.get("q_wxyz", true)) {
    if (auto R = RotationFromQuaternion(*qn)) x.R = *R;
  }
  if (auto v = n.vec3("v", true)) x.v = *v;
  if (auto bg = n.vec3("bg", false)) x.bg = *bg;
  if (auto ba = n.vec3("ba", false)) x.ba = *ba;
  if (n.checker().count() != before) return std::nullopt;
  return x;
}

ImuState ReadStateFile(const std::string& path) { return ReadJsonFileAs(path, StateFromJson); }

}  // namespace imuconv::pipeline
