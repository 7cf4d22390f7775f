#include "imuconv/pipeline/json_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "imuconv/pipeline/json_writer.h"
#include "input_checks.h"
#include "imuconv/so3.h"

namespace imuconv::pipeline {

json Vec3ToJson(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

json MatrixToJson(const Eigen::MatrixXd& m) {
  json rows = json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    json r = json::array();
    for (Eigen::Index k = 0; k < m.cols(); ++k) r.push_back(m(i, k));
    rows.push_back(std::move(r));
  }
  return rows;
}

json StateToJson(const ImuState& x) {
  const Eigen::Vector4d q = so3::ToQuaternionWxyz(x.R);
  return {{"p", Vec3ToJson(x.p)},
          {"q_wxyz", json::array({q[0], q[1], q[2], q[3]})},
          {"v", Vec3ToJson(x.v)},
          {"bg", Vec3ToJson(x.bg)},
          {"ba", Vec3ToJson(x.ba)}};
}

json NoiseToJson(const ImuNoise& n) {
  return {{"gyro_noise_density", n.gyro_noise_density},
          {"accel_noise_density", n.accel_noise_density},
          {"gyro_random_walk", n.gyro_random_walk},
          {"accel_random_walk", n.accel_random_walk}};
}

json ChartMatrixToJson(const Eigen::MatrixXd& m, const std::string& convention, const std::vector<std::string>& blocks) {
  return {{"convention", convention}, {"blocks", blocks}, {"matrix", MatrixToJson(m)}};
}

json MixedMatrixToJson(const Eigen::MatrixXd& m, const std::string& row_convention,
                       const std::vector<std::string>& row_blocks, const std::string& col_convention,
                       const std::vector<std::string>& col_blocks) {
  return {{"rows", {{"convention", row_convention}, {"blocks", row_blocks}}},
          {"cols", {{"convention", col_convention}, {"blocks", col_blocks}}},
          {"matrix", MatrixToJson(m)}};
}

std::vector<std::string> Blocks(const Registry& reg, PluginKind kind, const std::string& id) {
  return reg.info(kind, id).blocks;
}

std::optional<ImuState> StateFromJson(const Node& n) {
  if (!n.expect_object({"p", "q_wxyz", "v", "bg", "ba"})) return std::nullopt;
  const std::size_t before = n.checker().count();
  ImuState x;
  if (auto p = n.vec3("p", true)) x.p = *p;
  if (auto qn = n.get("q_wxyz", true))
    if (auto R = RotationFromQuaternion(*qn)) x.R = *R;
  if (auto v = n.vec3("v", true)) x.v = *v;
  if (auto bg = n.vec3("bg", false)) x.bg = *bg;
  if (auto ba = n.vec3("ba", false)) x.ba = *ba;
  if (n.checker().count() != before) return std::nullopt;
  return x;
}

std::optional<ImuNoise> NoiseFromJson(const Node& n) {
  if (!n.expect_object({"gyro_noise_density", "accel_noise_density", "gyro_random_walk", "accel_random_walk"}))
    return std::nullopt;
  const std::size_t before = n.checker().count();
  ImuNoise q;
  const auto read = [&](const char* key, double& out) {
    if (auto v = n.number(key, true)) {
      if (*v < 0.0)
        n.checker().error(n.child_pointer(key), "expected a non-negative number");
      else
        out = *v;
    }
  };
  read("gyro_noise_density", q.gyro_noise_density);
  read("accel_noise_density", q.accel_noise_density);
  read("gyro_random_walk", q.gyro_random_walk);
  read("accel_random_walk", q.accel_random_walk);
  if (n.checker().count() != before) return std::nullopt;
  return q;
}

std::optional<Matrix15In> Matrix15FromJson(const Node& n) {
  Matrix15In out;
  out.pointer = n.pointer();
  const std::size_t before = n.checker().count();
  if (n.is_array()) {
    if (auto m = n.matrix(15, 15)) out.m = *m;
  } else if (n.is_object() && n.has("diagonal")) {
    n.expect_object({"diagonal", "convention", "blocks"});
    if (auto d = n["diagonal"].vector(15)) out.m = d->asDiagonal();
  } else if (n.is_object() && n.has("sigma")) {
    n.expect_object({"sigma", "convention", "blocks"});
    if (auto d = n["sigma"].vector(15)) out.m = d->cwiseAbs2().asDiagonal();
  } else if (n.is_object()) {
    n.expect_object({"matrix", "convention", "blocks"});
    if (auto mn = n.get("matrix", true))
      if (auto m = mn->matrix(15, 15)) out.m = *m;
  } else {
    n.fail("expected a 15x15 matrix (an array of 15 rows), {\"diagonal\": [15 numbers]}, {\"sigma\": [15 numbers]} or {\"convention\", \"blocks\", \"matrix\"}; found " +
           TypeName(n.value()));
    return std::nullopt;
  }
  if (n.is_object()) {
    if (auto c = n.string("convention", false)) out.convention = *c;
    if (auto b = n.get("blocks", false)) {
      auto labels = b->string_list();
      if (labels && labels->size() != 5)
        b->fail("expected 5 block labels");
      else if (labels)
        out.blocks = *labels;
    }
  }
  if (n.checker().count() != before) return std::nullopt;
  if (!out.m.allFinite()) {
    n.fail("matrix has non-finite entries");
    return std::nullopt;
  }
  return out;
}

std::string PrettyJson(const json& j) {
  std::string out;
  JsonWriter w(out, 0, {}, JsonWriter::NonFinite::Null);
  w.value(j);
  out += "\n";
  return out;
}

ImuState ReadStateFile(const std::string& path) {
  const json j = ParseJsonFile(path);
  Checker c(path);
  const auto x = StateFromJson(Node(j, "", c));
  c.throw_if_errors();
  return *x;
}

}  // namespace imuconv::pipeline
