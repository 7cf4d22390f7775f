// IMU and ground-truth readers. Files are streamed line by line.
//
// Time handling: a timestamp is read exactly as written (an integer part as int64 and the
// fractional part separately), made relative to a time origin, and only then converted to
// double seconds. EuRoC's nanosecond stamps (~1.4e18, beyond double's 2^53) therefore lose
// nothing; the origin is kept so that outputs can report absolute times.
//
// Every reader takes ReadOptions (timing.h): the timing policy (gaps longer than
// max_gap_factor x the median period, and implausible rates, are errors) and the time range
// the tasks need (`keep`: only the rows in it, plus one on each side, are kept; every line is
// still validated, and the timing checks judge the kept rows). Inputs must be regular files:
// a FIFO or a device is refused without blocking.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "imuconv/pipeline/timing.h"
#include "imuconv/types.h"

namespace imuconv::pipeline {

/// A timestamp in some unit: whole units (exact) plus a fraction of one unit in [0, 1).
struct TimeValue {
  std::int64_t whole = 0;
  double frac = 0.0;
};

/// Parses a decimal timestamp ("1403715273262142976", "1403715273.262143", "-0.5", "1.5e-3").
/// Plain decimals keep every digit: the integer part exactly, the fraction to double
/// precision. Exponent forms go through double. Returns nothing for anything else
/// (including nan, inf and trailing garbage).
std::optional<TimeValue> ParseTimeValue(std::string_view text);
/// A JSON-number timestamp split the same way (integers exactly). Values beyond +-9e18 or not
/// finite cannot be represented; they saturate at the int64 range (the caller should refuse
/// them first, as ParseTimeValue does).
TimeValue TimeValueFromDouble(double t);

/// The time origin of a data set: absolute time = origin + relative time.
struct TimeOrigin {
  TimeValue value;  ///< in `unit`
  TimeUnit unit = TimeUnit::s;
  /// Seconds from the origin to a time given in the same unit (exact difference first).
  double relative_seconds(const TimeValue& t) const;
  /// The origin in integer nanoseconds (the fraction rounded); nothing if out of range.
  std::optional<std::int64_t> nanoseconds() const;
  /// Absolute nanoseconds of a relative time in seconds (rounded to 1 ns).
  std::optional<std::int64_t> absolute_ns(double relative_seconds) const;
};

struct ImuData {
  std::vector<ImuSample> samples;    ///< strictly increasing t, seconds relative to `origin`
  std::optional<TimeOrigin> origin;  ///< absent for inline samples without a time_origin
  std::string source;                ///< file path, or "inline"
  /// Suspected unit or column-order mistakes, with their evidence (imu_plausibility.h); the
  /// readers fill it, the commands print it as warnings.
  std::vector<std::string> warnings;
};

/// EuRoC IMU CSV: `#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z`, integer nanoseconds, rad/s,
/// m/s^2. Lines starting with '#' and blank lines are skipped; every other line must have
/// exactly 7 numeric fields. `origin_ns` defaults to the first sample's timestamp (of the
/// file, whether or not it is in options.keep).
ImuData ReadEurocImu(const std::string& path, std::optional<std::int64_t> origin_ns = std::nullopt,
                     const ReadOptions& options = {});

/// A column of a generic CSV: a 0-based index or a header name.
using ColumnRef = std::variant<int, std::string>;

struct CsvFormat {
  char delimiter = ',';
  bool whitespace_delimited = false;  ///< fields separated by runs of spaces/tabs
  int header_rows = 0;                ///< lines skipped at the top; names come from the first
  std::string comment;                ///< lines starting with this prefix are skipped ("" = none)
  TimeUnit time_unit = TimeUnit::s;
  /// t, wx, wy, wz, ax, ay, az.
  std::array<ColumnRef, 7> columns{0, 1, 2, 3, 4, 5, 6};
  std::optional<TimeValue> time_origin;  ///< in time_unit; default: the first sample
};

/// The names of the seven columns of CsvFormat::columns.
extern const std::array<const char*, 7> kImuColumnNames;

/// A column index must be below the header's width (when there is a header) and below the
/// first data row's field count; every data row must have the same count.
ImuData ReadCsvImu(const std::string& path, const CsvFormat& format,
                   const ReadOptions& options = {});

/// A ground-truth trajectory on the same time axis as the IMU data.
struct GroundTruth {
  std::vector<double> t;  ///< seconds relative to the IMU origin, strictly increasing
  std::vector<ImuState> x;
  std::string source;
  /// False for pose-only ground truth (TUM, EuRoC vicon0): x holds R and p, its v and biases
  /// are zero and must not be used (RunContext::gt_at refuses them).
  bool full_state = true;
  std::string format = "euroc";  ///< the pipeline's /ground_truth/format, for messages
  /// The state at t: p, v, bg, ba interpolated linearly, R by slerp. Nothing outside [t0, tN].
  std::optional<ImuState> at(double t) const;
};

/// EuRoC/ASL ground truth (state_groundtruth_estimate0/data.csv, or OpenVINS' vicon2gt
/// files): `#time(ns), p xyz, q wxyz, v xyz, bg xyz, ba xyz` (17 fields), made relative to
/// `origin` (the IMU data's origin). Gaps between rows are judged by options.timing like IMU
/// gaps: they would be interpolated across and used as start states.
GroundTruth ReadEurocGroundTruth(const std::string& path, const TimeOrigin& origin,
                                 const ReadOptions& options = {});

/// A pose of the ground-truth sensor S (e.g. a Vicon marker) in the body (IMU) frame B:
/// EuRoC's sensor.yaml T_BS. The body's pose is then T_RB = T_RS T_BS^-1.
struct SensorInBody {
  Mat3 R_BS = Mat3::Identity();
  Vec3 p_BS = Vec3::Zero();
};

/// Pose-only ground truth, read with full_state = false:
///   "tum":        `t x y z qx qy qz qw`, t in seconds, separated by blanks ('#' comments);
///   "euroc_pose": EuRoC vicon0/data.csv, `#timestamp [ns], p xyz, q wxyz` (8 fields).
/// Quaternions are Hamilton, sensor to world, unit within 1e-3 (files with 6 digits).
/// `sensor` (T_BS) maps the sensor's poses to the body's.
GroundTruth ReadPoseGroundTruth(const std::string& path, const std::string& format,
                                const TimeOrigin& origin, const ReadOptions& options = {},
                                const SensorInBody& sensor = {});

}  // namespace imuconv::pipeline
