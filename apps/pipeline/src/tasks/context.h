// What the stages and the tasks share while a pipeline runs (internal to imuconv_pipeline):
// the registry and the plugin handles resolved from it, the IMU data, the ground truth and
// the time origin, the measurement files, and the results of the tasks a later task names.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "../forms/comparison.h"
#include "../forms/intervals.h"
#include "../io/output.h"
#include "../spec/pipeline_spec.h"
#include "imuconv/bridge.h"
#include "imuconv/pipeline/measurement.h"
#include "imuconv/pipeline/run_options.h"
#include "results.h"

namespace imuconv::pipeline {

/// The "FILE: POINTER: message" error of one task at run time.
class TaskFailure : public Error {
 public:
  using Error::Error;
};

class RunContext {
 public:
  RunContext(const PipelineSpec& s, const Registry& r, const RunOptions& o, Output& out);

  const PipelineSpec& spec;
  const Registry& reg;
  const RunOptions& opt;
  Output& out;

  // ---- data, filled by the load stage ----
  ImuData imu;
  bool have_imu = false;
  std::optional<std::int64_t> origin_ns;
  std::optional<GroundTruth> gt;
  std::optional<std::pair<double, double>> imu_keep, gt_keep;  ///< the time ranges read into memory
  std::map<std::string, std::vector<MeasRecord>> files;  ///< measurement files by resolved path

  // ---- results and resolved plugins ----
  /// The tasks a later task names: name -> the pointer of the first reference.
  std::unordered_map<std::string, std::string> referenced;
  /// Results of the referenced tasks, and nothing else.
  std::map<std::string, TaskResult> results;
  /// Each preintegrate task's method, resolved once when the registry is checked.
  std::unordered_map<const Task*, PreintegrationMethod> methods;

  std::ostream* summary() const { return opt.summary; }
  /// Throws TaskFailure "FILE: POINTER: message".
  [[noreturn]] void fail(const std::string& pointer, const std::string& message) const;
  /// A later task names task `name`: its results are kept (else written and dropped).
  bool kept(const std::string& name) const { return referenced.count(name) > 0; }
  /// The type of the task `name` ("?" when there is none).
  const std::string& type_of(const std::string& name) const;

  /// The IMU samples over [ts, te].
  SampleWindow window(double ts, double te) const;
  /// The ground-truth state at t (TaskFailure at `pointer` when it has none there).
  ImuState gt_at(double t, const std::string& pointer) const;
  /// A prediction at t against the ground truth: position and rotation errors, and the
  /// velocity error and left-chart error vector when the ground truth is a full state.
  GtComparison compare_gt(const ImuState& predicted, double t, const std::string& pointer) const;
  /// Whether there is ground truth at t.
  bool gt_covers(double t) const { return gt && gt->at(t).has_value(); }
  const std::vector<MeasRecord>& measurements(const MeasurementsSpec& m) const;
  /// The indices of the measurements a task uses: all of them, or the one at `index`
  /// (TaskFailure at task_pointer/index when out of range; `what` names the measurements).
  std::vector<std::size_t> select(const std::vector<MeasRecord>& ms,
                                  const std::optional<std::size_t>& index,
                                  const std::string& task_pointer, const std::string& what) const;
  /// Block labels of a registered plugin.
  const std::vector<std::string>& blocks(PluginKind kind, const std::string& id) const {
    return reg.info(kind, id).blocks;
  }
  /// A start covariance in the chart `conv` at x (zero when none is given).
  Mat15 start_cov(const CovSpec& cov, const std::string& conv, const ImuState& x) const;
  /// WriteTimes with the data's time origin.
  void write_times(JsonWriter& w, std::optional<double> ts, std::optional<double> te) const;

  // ---- checks (the stages "check ids" and "check times") ----
  void check_id(Checker& c, PluginKind kind, const std::string& id,
                const std::string& pointer) const;
  /// The chart a given covariance names (and its block order) against the registry.
  void check_cov_convention(Checker& c, const CovSpec& cov, PluginKind kind,
                            const std::string& target) const;
  /// t within the IMU data.
  void check_time(Checker& c, double t, const std::string& pointer) const;
  /// t within the ground truth, when there is one.
  void check_gt(Checker& c, double t, const std::string& pointer) const;
  /// check_gt for a use of the whole state (a start state, a bias estimate): also that the
  /// ground truth has velocity and biases.
  void check_gt_state(Checker& c, double t, const std::string& pointer) const;
  /// Every keyframe within the IMU data (one message for generated keyframes), and every
  /// interval holding an IMU sample (check_intervals_hold_samples).
  void check_interval_times(Checker& c, const IntervalsSpec& iv) const;
  /// Unless /allow_empty_intervals: every interval inside the data holds at least one IMU
  /// sample (its ends included, within kSameInstant). An interval shorter than the sample
  /// period between two samples is all interpolation: keyframes finer than the samples are
  /// almost always a unit slip in the step (2.1e-7 s for 0.21 s), and at that step 1.9 s of
  /// data are 9 million intervals and gigabytes of output. Checked in the "check times"
  /// stage, before any interval is integrated, in one pass over keyframes and samples.
  void check_intervals_hold_samples(Checker& c, const IntervalsSpec& iv) const;

 private:
  std::string gt_uncovered(double t) const;
  std::unordered_map<std::string, const Task*> by_name_;
};

}  // namespace imuconv::pipeline
