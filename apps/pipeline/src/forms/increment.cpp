// The increment form, read and written (increment.h).
#include "increment.h"

#include <cmath>
#include <sstream>

#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/so3.h"
#include "input_checks.h"

namespace imuconv::pipeline {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
// Two statements of one rotation (q_wxyz, R, rotation_angle_deg) agree within this many
// degrees: well above the round-off of written numbers (1e-13 deg), well below any real
// disagreement.
constexpr double kRotationAgreementDeg = 1e-6;

std::string IncrementNum(double v, int precision) {
  std::ostringstream o;
  o.precision(precision);
  o << v;
  return o.str();
}

}  // namespace

double RotationAngleDeg(const Mat3& R) { return so3::Log(R).norm() * kRadToDeg; }

std::optional<PreintIncrement> IncrementFromJson(const Node& n) {
  if (!n.expect_object({"q_wxyz", "R", "dp", "dv", "dbg", "dba", "rotation_angle_deg"}))
    return std::nullopt;
  const std::size_t before = n.checker().count();
  PreintIncrement d;
  std::optional<Mat3> Rq, Rm;
  if (auto qn = n.get("q_wxyz", false)) Rq = RotationFromQuaternion(*qn);
  if (auto rn = n.get("R", false)) Rm = RotationFromMatrix(*rn);
  if (!n.has("q_wxyz") && !n.has("R"))
    n.checker().error(n.child_pointer("q_wxyz"), "required key is missing (give q_wxyz or R)");
  if (Rq && Rm) {
    const double disagree = RotationAngleDeg(Rq->transpose() * *Rm);
    if (disagree > kRotationAgreementDeg)
      n.checker().error(
          n.child_pointer("R"),
          "R and q_wxyz disagree by " + IncrementNum(disagree, 6) + " deg (tolerance 1e-6 deg)");
  }
  const std::optional<Mat3> R = Rq ? Rq : Rm;
  if (auto an = n.get("rotation_angle_deg", false))
    if (auto a = an->number();
        a && R && std::abs(*a - RotationAngleDeg(*R)) > kRotationAgreementDeg)
      an->fail("rotation_angle_deg = " + IncrementNum(*a, 12) +
               " does not match the rotation's angle " + IncrementNum(RotationAngleDeg(*R), 12) +
               " deg (tolerance 1e-6 deg)");
  if (R) d.dR = *R;
  if (auto v = n.vec3("dp", true)) d.dp = *v;
  if (auto v = n.vec3("dv", true)) d.dv = *v;
  if (auto v = n.vec3("dbg", false)) d.dbg = *v;
  if (auto v = n.vec3("dba", false)) d.dba = *v;
  if (n.checker().count() != before) return std::nullopt;
  return d;
}

void WriteIncrement(JsonWriter& w, const PreintIncrement& d, bool with_R) {
  const auto put = [&w](const char* key, const auto& v) {
    w.key(key);
    w.vector(v);
  };
  w.begin_object();
  put("q_wxyz", so3::ToQuaternionWxyz(d.dR));
  if (with_R) {
    w.key("R");
    w.matrix(d.dR);
  }
  put("dp", d.dp);
  put("dv", d.dv);
  put("dbg", d.dbg);
  put("dba", d.dba);
  w.key("rotation_angle_deg");
  w.number(RotationAngleDeg(d.dR));
  w.end_object();
}

PreintIncrement ReadIncrementFile(const std::string& path) {
  return ReadJsonFileAs(path, IncrementFromJson);
}

}  // namespace imuconv::pipeline
