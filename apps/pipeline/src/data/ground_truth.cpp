// The EuRoC / vicon2gt ground-truth reader and the interpolation of its states.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/ground_truth_quaternion.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/so3.h"
#include "row_loop.h"

namespace imuconv::pipeline {

std::optional<ImuState> GroundTruth::at(double tq) const {
  if (t.empty() || x.size() != t.size() || !(tq >= t.front()) || !(tq <= t.back()))
    return std::nullopt;
  const std::size_t i =
      static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), tq) - t.begin());
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
const char* const kGtNames[kGtFields] = {
    "timestamp [ns]", "p_x",  "p_y",  "p_z",  "q_w",  "q_x", "q_y", "q_z", "v_x", "v_y", "v_z",
    "bg_x",           "bg_y", "bg_z", "ba_x", "ba_y", "ba_z"};
}  // namespace

GroundTruth ReadEurocGroundTruth(const std::string& path, const TimeOrigin& origin,
                                 const ReadOptions& options) {
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
    if (const auto problem =
            GroundTruthQuaternionProblem(v[4], v[5], v[6], v[7], "(q_w, q_x, q_y, q_z)"))
      row.fail(*problem);
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

GroundTruth ReadPoseGroundTruth(const std::string& path, const std::string& format,
                                const TimeOrigin& origin, const ReadOptions& options,
                                const SensorInBody& sensor) {
  const bool tum = format == "tum";
  if (!tum && format != "euroc_pose")
    throw ReadError(path, 0, "unknown pose ground-truth format '" + format + "'");
  data::LineReader lr(path);
  data::RowFormat rf;
  rf.comment = "#";
  rf.n_fields = 8;
  rf.source = TimeSource::ground_truth;
  rf.row_noun = "row";
  rf.empty = "contains no ground-truth rows";
  // Field indices of p xyz and of the quaternion's w, x, y, z in each format.
  std::size_t ip = 1, iw, ix;
  if (tum) {
    rf.whitespace_delimited = true;
    rf.fields_what = " (TUM: t x y z qx qy qz qw)";
    rf.time_label = "t";
    rf.time_what = "a time in seconds";
    rf.unit = TimeUnit::s;
    iw = 7;
    ix = 4;
  } else {
    rf.fields_what = " (EuRoC vicon0: timestamp [ns], p xyz, q wxyz)";
    rf.time_label = "timestamp [ns]";
    rf.integer_time = true;
    rf.time_what = "an integer timestamp in nanoseconds";
    rf.unit = TimeUnit::ns;
    iw = 4;
    ix = 5;
  }
  static const char* const kNames[8] = {"t", "p_x", "p_y", "p_z", "q", "q", "q", "q"};
  data::RowLoop loop(path, lr, std::move(rf), origin);
  const Mat3 R_SB = sensor.R_BS.transpose();
  auto kept = data::ReadRows<ImuState>(loop, options, [&](const data::RowLoop& row) {
    double v[8];
    for (std::size_t k = 1; k < 8; ++k) v[k] = row.number(k, kNames[k]);
    const double qw = v[iw], qx = v[ix], qy = v[ix + 1], qz = v[ix + 2];
    if (const auto problem = GroundTruthQuaternionProblem(
            qw, qx, qy, qz, tum ? "(qx, qy, qz, qw)" : "(q_w, q_x, q_y, q_z)"))
      row.fail(*problem);
    // The sensor's pose T_RS, then the body's: R_RB = R_RS R_SB, p_RB = p_RS - R_RB p_BS.
    ImuState s;
    s.R = so3::FromQuaternionWxyz(qw, qx, qy, qz) * R_SB;
    s.p = Vec3(v[ip], v[ip + 1], v[ip + 2]) - s.R * sensor.p_BS;
    return s;
  });
  GroundTruth gt;
  gt.source = path;
  gt.full_state = false;
  gt.format = format;
  gt.t = std::move(kept.times());
  gt.x = std::move(kept.rows());
  return gt;
}

}  // namespace imuconv::pipeline
