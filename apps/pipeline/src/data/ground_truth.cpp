// The EuRoC / vicon2gt ground-truth reader and the interpolation of its states.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "imuconv/pipeline/imu_reader.h"
#include "row_loop.h"
#include "imuconv/so3.h"

namespace imuconv::pipeline {

std::optional<ImuState> GroundTruth::at(double tq) const {
  if (t.empty() || x.size() != t.size() || !(tq >= t.front()) || !(tq <= t.back())) return std::nullopt;
  const std::size_t i = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), tq) - t.begin());
  if (t[i] == tq) return x[i];
  // tq > t.front() here, so i >= 1.
  const ImuState& a = x[i - 1];
  const ImuState& b = x[i];
  const double u = (tq - t[i - 1]) / (t[i] - t[i - 1]);
  ImuState s;
  s.p = a.p + u * (b.p - a.p);
  s.v = a.v + u * (b.v - a.v);
  s.bg = a.bg + u * (b.bg - a.bg);
  s.ba = a.ba + u * (b.ba - a.ba);
  // Geodesic interpolation: R_a Exp(u Log(R_a^T R_b)).
  s.R = a.R * so3::Exp(u * so3::Log(a.R.transpose() * b.R));
  return s;
}

namespace {
constexpr std::size_t kGtFields = 17;
const char* const kGtNames[kGtFields] = {"timestamp [ns]", "p_x", "p_y", "p_z", "q_w",  "q_x",  "q_y",  "q_z", "v_x",
                                         "v_y",            "v_z", "bg_x", "bg_y", "bg_z", "ba_x", "ba_y", "ba_z"};

std::string Fixed(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}
}  // namespace

GroundTruth ReadEurocGroundTruth(const std::string& path, const TimeOrigin& origin, const ReadOptions& options) {
  data::LineReader lr(path);
  data::RowFormat rf;
  rf.comment = "#";
  rf.n_fields = kGtFields;
  rf.fields_what = " (timestamp [ns], p xyz, q wxyz, v xyz, bg xyz, ba xyz)";
  rf.time_label = kGtNames[0];
  rf.integer_time = true;
  rf.time_what = "an integer timestamp in nanoseconds";
  rf.unit = TimeUnit::ns;
  // Holes are judged like IMU gaps: they would be interpolated across and the result used as
  // a start state.
  rf.source = TimeSource::ground_truth;
  rf.row_noun = "row";
  rf.empty = "contains no ground-truth rows";
  data::RowLoop loop(path, lr, std::move(rf), origin);
  auto kept = data::ReadRows<ImuState>(loop, options, [](const data::RowLoop& row) {
    double v[kGtFields];
    for (std::size_t k = 1; k < kGtFields; ++k) v[k] = row.number(k, kGtNames[k]);
    const double qn = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    // 1e-3: the tolerance for quaternions written with 6 significant digits (EuRoC's files).
    if (!(std::abs(qn - 1.0) <= 1e-3))
      row.fail("quaternion (q_w, q_x, q_y, q_z) has norm " + Fixed(qn) + ", expected 1 (to 1e-3)");
    ImuState s;
    s.p = Vec3(v[1], v[2], v[3]);
    s.R = so3::FromQuaternionWxyz(v[4], v[5], v[6], v[7]);
    s.v = Vec3(v[8], v[9], v[10]);
    s.bg = Vec3(v[11], v[12], v[13]);
    s.ba = Vec3(v[14], v[15], v[16]);
    return s;
  });
  GroundTruth gt;
  gt.source = path;
  gt.t = std::move(kept.times());
  gt.x = std::move(kept.rows());
  return gt;
}

}  // namespace imuconv::pipeline
