// The parsed form of a pipeline document (internal to imuconv_pipeline).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "imuconv/bridge.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/json_io.h"

namespace imuconv::pipeline {

// ---- sources --------------------------------------------------------------------------
struct ImuSourceSpec {
  enum class Format { Euroc, Csv, Inline } format = Format::Euroc;
  std::string path;  // resolved
  std::optional<std::int64_t> origin_ns;  // euroc
  CsvFormat csv;                          // csv (and time_unit/time_origin for inline)
  std::vector<ImuSample> inline_raw;      // inline: t in time units (not yet relative)
  std::vector<TimeValue> inline_t;
  std::vector<std::size_t> inline_index;  // inline: the index of each kept sample in "samples"
  TimingPolicy timing;  // max_gap_factor, allow_gaps
  std::string pointer;
};

struct GroundTruthSpec {
  std::string path;  // resolved
  TimingPolicy timing;
  std::string pointer;
};

// ---- task pieces ----------------------------------------------------------------------
/// Interval boundaries: one interval [t0, t1] or consecutive keyframe pairs. Explicit times
/// ("interval", a keyframes array) are stored; a generated {start, end, step} form is not
/// (a tiny step must not cost memory per keyframe): its keyframes are start + k step and,
/// last, `end` itself. A remainder of (end - start) shorter than a step, beyond round-off
/// (1e-9 of a step), is a last, shorter interval ending at `end`.
struct IntervalsSpec {
  enum class Form { Interval, Array, Generated } form = Form::Interval;
  std::vector<double> times;  // Interval, Array
  double start = 0, step = 0, end = 0;  // Generated
  std::size_t count = 0;                // Generated: number of keyframes
  bool short_last = false;              // Generated: the last interval is a remainder
  std::string pointer;  // the "interval" or "keyframes" node

  std::size_t size() const { return form == Form::Generated ? count : times.size(); }
  /// Keyframe k (k < size()).
  double time(std::size_t k) const;
  double front() const { return time(0); }
  double back() const { return time(size() - 1); }
  /// The pointer of keyframe k, for messages: its own for explicit times, start or end
  /// (or the keyframes object, for an interior one) for the generated form.
  std::string pointer_of(std::size_t k) const;
};

struct StateSpec {
  bool ground_truth = false;
  ImuState x;
  std::string pointer;
};

struct BiasSpec {
  bool ground_truth = false;
  Vec3 bg = Vec3::Zero(), ba = Vec3::Zero();
  std::string pointer;
};

/// A 15x15 covariance input; `convention` when the matrix names one. Held by pointer: a
/// task is then small (~1 KB, not ~3 KB), which counts for pipelines of 100 000 tasks.
struct CovSpec {
  bool given = false;
  std::shared_ptr<const Matrix15In> in;
  const Matrix15In& m() const { return *in; }
};

/// Measurements from an earlier task or from a file (already read and checked for shape).
struct MeasurementFileEntry {
  std::optional<double> t_start, t_end;
  PreintegratedIn m;
  std::string pointer;  // in the file
  std::optional<std::vector<std::string>> cov_blocks, jac_rows, jac_cols;
};
struct MeasurementsSpec {
  std::string task;  // or
  std::string file;  // resolved
  std::vector<MeasurementFileEntry> entries;  // file only
  std::string pointer;
};

// ---- tasks ----------------------------------------------------------------------------
struct PropagateTask {
  std::string propagator, convention = "left";
  StateSpec start;
  CovSpec cov;
  IntervalsSpec interval;
  std::optional<bool> compare_gt;
};

struct PreintegrateTask {
  bool native = false;  // preintegrator (true) or propagator (false)
  std::string method_id;
  std::string method_pointer;
  std::vector<std::string> conventions;
  std::string conventions_pointer;
  BiasSpec bias;
  IntervalsSpec intervals;
};

struct PropByPreintTask {
  MeasurementsSpec meas;
  std::string convention = "left";
  StateSpec start;
  CovSpec cov;
  bool chain = false;
  std::optional<bool> compare_gt;
};

struct ConvertTask {
  enum class What { StateJacobian, StateCovariance, StateTransition, IncrementJacobian, IncrementCovariance } what{};
  std::string what_name;
  std::optional<std::string> from;
  std::string to;
  std::optional<ImuState> state, state_end;
  std::optional<PreintIncrement> increment;
  std::shared_ptr<const Matrix15In> matrix;  // by pointer, as CovSpec
  std::optional<std::string> source_task;
  std::size_t source_index = 0;
  std::string from_pointer, to_pointer, source_pointer;
};

struct ResidualTask {
  ResidualKind kind = ResidualKind::Gtsam;
  std::string kind_name;
  MeasurementsSpec meas;
  std::string convention = "left";
  StateSpec start, end;
  std::optional<std::size_t> index;
};

struct BiasUpdateTask {
  MeasurementsSpec meas;
  bool relative = false;  // delta_bg/delta_ba rather than bg/ba
  Vec3 bg = Vec3::Zero(), ba = Vec3::Zero();
  std::vector<std::string> charts;  // first-order correction charts
  std::string charts_pointer;
  bool reintegrate = true;
  std::optional<std::size_t> index;
};

struct TaskSpec {
  std::string type, name, description, pointer;
  std::variant<PropagateTask, PreintegrateTask, PropByPreintTask, ConvertTask, ResidualTask, BiasUpdateTask> body;
};

/// What the output leaves out (the top-level "omit" list).
struct OmitSpec {
  bool Phi = false;        ///< transition matrices (propagate, propagate_by_preintegration steps)
  bool cov = false;        ///< covariances of measurements, propagations and steps
  bool J_bias = false;     ///< bias Jacobians of measurements
  bool R = false;          ///< rotation matrices of increments (q_wxyz stays)
  bool reference = false;  ///< a measurement's preint_reference J_bias and cov when it is expressed in other conventions
};

struct PipelineSpec {
  std::string file, base_dir;
  OmitSpec omit;
  std::string description;
  std::vector<std::string> plugin_dirs;
  bool allow_plugin_override = false;
  std::optional<std::string> output;
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  ImuNoise noise;
  std::optional<ImuSourceSpec> imu;
  std::optional<GroundTruthSpec> gt;
  std::vector<TaskSpec> tasks;
};

/// Parses and validates the structure; throws ConfigError listing every issue.
std::unique_ptr<PipelineSpec> ParseSpec(const json& doc, const std::string& file, const std::string& base_dir);

}  // namespace imuconv::pipeline
