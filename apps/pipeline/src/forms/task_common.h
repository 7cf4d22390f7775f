// The pieces several task kinds share: their parsed forms, readers and writers.
//   "start": {"state": STATE | "ground_truth", "cov": MATRIX15}    propagate,
//   propagate_by_preintegration "bias": {"bg", "ba"} | "ground_truth" preintegrate "measurements":
//   NAME | {"file": PATH}                         tasks that read measurements t_start, t_end (and
//   *_abs_ns) of an interval                  every interval result
// and what a task's parser sees of the document (ParseContext).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/json_writer.h"
#include "imuconv/pipeline/omit.h"

namespace imuconv::pipeline {

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
/// task is then small, which counts for pipelines of 100 000 tasks.
struct CovSpec {
  bool given = false;
  std::shared_ptr<const Matrix15In> in;
  const Matrix15In& m() const { return *in; }
};

/// Measurements from an earlier preintegrate task (`task`) or from a file (`file`, resolved).
struct MeasurementsSpec {
  std::string task;
  std::string file;
  std::string pointer;
};

/// What a task's parser sees of the document: its checker and directory, which top-level
/// sources there are, and the earlier tasks (looked up once per reference, so that
/// validation stays linear in the number of tasks).
class ParseContext {
 public:
  ParseContext(Checker& c, std::string base_dir) : c_(c), base_dir_(std::move(base_dir)) {}
  Checker& checker() const { return c_; }
  /// A path from the document, relative to its directory unless absolute.
  std::string resolve(const std::string& path) const;
  bool has_imu = false, has_gt = false;
  /// The type of the earlier task `name`, or nothing ("?" for a task of unknown type).
  const std::string* earlier(const std::string& name) const;
  void remember(const std::string& name, const std::string& type);
  /// "'a', 'b' and 3 more": the earlier preintegrate tasks, for messages.
  std::string earlier_preintegrate_names() const;

 private:
  Checker& c_;
  std::string base_dir_;
  std::unordered_map<std::string, std::string> earlier_;
  std::vector<std::string> preintegrate_names_;  // the first few, in order
  std::size_t preintegrate_count_ = 0;
};

/// A state: an object, or "ground_truth" (which needs a /ground_truth source).
std::optional<StateSpec> ReadStateSpec(const ParseContext& ctx, const Node& n);
std::optional<BiasSpec> ReadBiasSpec(const ParseContext& ctx, const Node& n);
/// A start covariance: read, and refused (never repaired) unless it is one.
std::optional<CovSpec> ReadCovSpec(const Node& n);
/// "start": {"state": ..., "cov": ...} of `task`.
void ReadStart(const ParseContext& ctx, const Node& task, StateSpec& state, CovSpec& cov);
/// "measurements" of `task`: an earlier preintegrate task's name or {"file": PATH}.
std::optional<MeasurementsSpec> ReadMeasurementsSpec(const ParseContext& ctx, const Node& task);
/// A new task of type T (a task over measurements, with a `meas`) with the "measurements" of
/// `task` read into it (ReadMeasurementsSpec), before any other key.
template <typename T>
std::unique_ptr<T> NewMeasurementsTask(const ParseContext& ctx, const Node& task) {
  auto p = std::make_unique<T>();
  if (auto m = ReadMeasurementsSpec(ctx, task)) p->meas = *m;
  return p;
}
/// A plugin id at task[key] (not empty); `pointer` receives its pointer when given.
std::optional<std::string> ReadPluginId(const Node& task, const char* key, bool required,
                                        std::string* pointer = nullptr);
/// "index" (>= 0) of `task`, when given.
std::optional<std::size_t> ReadIndex(const Node& task);
/// "compare_ground_truth" of `task`, when given (true needs a /ground_truth source).
std::optional<bool> ReadCompareGroundTruth(const ParseContext& ctx, const Node& task);
/// Reports that a task of `type` needs the top-level /imu source, when there is none.
void RequireImu(const ParseContext& ctx, const Node& task, const std::string& type);

/// The keys t_start, t_end (and t_start_abs_ns, t_end_abs_ns when there is a time origin) of
/// the open object.
void WriteTimes(JsonWriter& w, std::optional<double> ts, std::optional<double> te,
                const std::optional<TimeOrigin>& origin);
/// "measurements": NAME | {"file": PATH}.
void WriteMeasurementsSource(JsonWriter& w, const MeasurementsSpec& m);
/// "task 'NAME'" or "file PATH", for messages and the summary.
std::string MeasurementsName(const MeasurementsSpec& m);

}  // namespace imuconv::pipeline
