// What a task leaves for later tasks, and which tasks must leave anything (internal).
//
// Memory is bounded by the work asked: a task's per-interval results are kept only when a
// later task names it ("measurements": NAME, or a convert task's "source"); every other
// task's intervals are written as they are computed and dropped. What must be kept is
// estimated before any task runs and refused beyond RunOptions::max_kept_bytes.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "imuconv/pipeline/measurement.h"

namespace imuconv::pipeline {

struct PipelineSpec;

struct PropRecord {
  ImuState x_s, x_e;
  Mat15 Phi = Mat15::Identity(), cov = Mat15::Zero();
  std::string convention;
  std::optional<double> t_s, t_e;
};

struct TaskResult {
  std::string type;
  std::vector<MeasRecord> meas;   ///< preintegrate: its measurements
  std::vector<PropRecord> props;  ///< propagate, propagate_by_preintegration: the propagations
  /// preintegrate: integrates a window again with another bias, as the task did (bias_update).
  std::function<Preintegrated(const SampleWindow& w, const Vec3& bg, const Vec3& ba)> reintegrate;
};

/// The tasks a later task names: name -> the pointer of the first reference.
std::unordered_map<std::string, std::string> ReferencedTasks(const PipelineSpec& s);

/// The records each referenced task will keep, estimated from the spec (and the sizes of the
/// measurement files, by `file_count`), summed in task order against `limit` bytes. Throws
/// ConfigError naming the task that crosses the limit, its count and the sizes. Returns the
/// estimate.
std::size_t CheckKeptMemory(const PipelineSpec& s,
                            const std::unordered_map<std::string, std::string>& referenced,
                            const std::function<std::size_t(const std::string& file)>& file_count,
                            std::size_t limit);

/// Bytes one kept record takes (the record and its heap parts, for the estimate).
std::size_t KeptBytes(const MeasRecord& r);
std::size_t KeptBytes(const PropRecord& r);

}  // namespace imuconv::pipeline
