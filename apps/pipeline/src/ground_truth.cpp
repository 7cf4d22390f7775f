// The EuRoC / vicon2gt ground-truth reader and the interpolation of its states.
#include <Eigen/Geometry>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "data/csv_text.h"
#include "data/line_reader.h"
#include "data/range_keeper.h"
#include "data/read_timing.h"
#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/imu_reader.h"
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
  using data::Shown;
  data::LineReader lr(path);
  std::string line;
  std::vector<std::string_view> fields;
  const std::int64_t npu = NanosPerUnit(origin.unit);
  std::int64_t prev_ns = 0;
  double prev_t = 0.0;
  std::size_t prev_line = 0;
  data::RangeKeeper<ImuState> keeper(options.keep);
  while (lr.next(line)) {
    if (data::IsBlank(line) || data::Trim(line).front() == '#') continue;
    const std::size_t ln = lr.line_no();
    data::Split(line, ',', false, fields);
    if (fields.size() != kGtFields)
      throw ReadError(path, ln,
                      "expected 17 fields (timestamp [ns], p xyz, q wxyz, v xyz, bg xyz, ba xyz) separated by ',', found " +
                          std::to_string(fields.size()));
    // From here on every index below 17 is in range.
    std::int64_t ns = 0;
    const auto r = std::from_chars(fields[0].data(), fields[0].data() + fields[0].size(), ns);
    if (fields[0].empty() || r.ec != std::errc() || r.ptr != fields[0].data() + fields[0].size())
      throw ReadError(path, ln,
                      "column 0 (timestamp [ns]): expected an integer timestamp in nanoseconds, found " + Shown(fields[0]));
    if (prev_line != 0 && ns <= prev_ns)
      throw ReadError(path, ln,
                      "timestamp " + std::to_string(ns) + " is not after the previous sample's (line " +
                          std::to_string(prev_line) + "); timestamps must be strictly increasing");
    double v[kGtFields];
    for (std::size_t k = 1; k < kGtFields; ++k) {
      const auto d = data::ParseDouble(fields[k]);
      if (!d || !std::isfinite(*d))
        throw ReadError(path, ln,
                        "column " + std::to_string(k) + " (" + kGtNames[k] + "): expected a finite number, found " +
                            Shown(fields[k]));
      v[k] = *d;
    }
    const double qn = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    // 1e-3: the tolerance for quaternions written with 6 significant digits (EuRoC's files).
    if (!(std::abs(qn - 1.0) <= 1e-3))
      throw ReadError(path, ln, "quaternion (q_w, q_x, q_y, q_z) has norm " + Fixed(qn) + ", expected 1 (to 1e-3)");
    // The stamp in the origin's unit, then relative to it.
    std::int64_t whole = ns / npu, rem = ns % npu;
    if (rem < 0) {
      whole -= 1;
      rem += npu;
    }
    const double t = origin.relative_seconds(TimeValue{whole, static_cast<double>(rem) / static_cast<double>(npu)});
    if (prev_line != 0 && !(t > prev_t))
      throw ReadError(path, ln, "timestamp is too close to the previous row's to be told apart in double seconds");
    prev_ns = ns;
    prev_t = t;
    prev_line = ln;
    ImuState s;
    s.p = Vec3(v[1], v[2], v[3]);
    s.R = so3::FromQuaternionWxyz(v[4], v[5], v[6], v[7]);
    s.v = Vec3(v[8], v[9], v[10]);
    s.bg = Vec3(v[11], v[12], v[13]);
    s.ba = Vec3(v[14], v[15], v[16]);
    keeper.add(t, ln, s);
  }
  if (keeper.times().empty()) throw ReadError(path, 0, "contains no ground-truth rows");
  // Holes are judged like IMU gaps, on the kept rows (see data/range_keeper.h): they would be
  // interpolated across and the result used as a start state.
  data::ThrowIfTimingIssue(path, keeper.times(), keeper.lines(), keeper.window(), options.timing, TimeUnit::ns,
                           TimeSource::ground_truth);
  GroundTruth gt;
  gt.source = path;
  gt.t = std::move(keeper.times());
  gt.x = std::move(keeper.rows());
  return gt;
}

}  // namespace imuconv::pipeline
