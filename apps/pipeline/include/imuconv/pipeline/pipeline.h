// JSON pipelines: an IMU source, noise, gravity and an ordered list of named tasks
// (propagate, preintegrate, propagate_by_preintegration, convert, residual, bias_update, check).
// The format is described by schemas/pipeline.schema.json and docs in examples/README.md.
//
// Loading validates the structure by hand and reports every problem with its JSON pointer
// (unknown keys included); running then checks plugin ids against the registry and times
// against the data (again with pointers) before any task runs, and produces one output
// JSON document. Nothing is written here: the caller writes the document (atomically).
//
// Inputs are checked, never repaired (covariances symmetric and positive semi-definite,
// unit quaternions, statements of one value that must agree, IMU and ground-truth gaps).
// Memory is bounded by the work asked: only the data range the tasks use is read into
// memory, and a task's per-interval results are kept only when a later task names it. The
// document records the file and version of every plugin the tasks used ("plugins").
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "imuconv/pipeline/json_check.h"
#include "imuconv/registry.h"

namespace imuconv::pipeline {

struct PipelineSpec;  // the parsed document (apps/pipeline/src/spec.h)

class Pipeline {
 public:
  /// Reads and validates a pipeline file; relative paths in it are relative to its directory.
  /// Throws ConfigError (every issue, with pointers) or ReadError (file cannot be opened).
  static Pipeline Load(const std::string& path);
  /// The same from a parsed document; `file` names it in messages, `base_dir` resolves paths.
  static Pipeline FromJson(const json& doc, const std::string& file, const std::string& base_dir);

  Pipeline(Pipeline&&) noexcept;
  Pipeline& operator=(Pipeline&&) noexcept;
  ~Pipeline();

  const std::string& file() const;
  /// The pipeline's plugin_dirs, resolved against its directory.
  const std::vector<std::string>& plugin_dirs() const;
  /// The pipeline's "output" key, resolved against its directory.
  const std::optional<std::string>& output_path() const;
  /// Every file the pipeline reads: the pipeline itself, the Kalibr noise file, the IMU and
  /// ground-truth files and the measurement files, each once, as resolved paths. An output must be none of them.
  std::vector<std::string> input_files() const;
  /// The names of the tasks whose steps RunOptions::on_step receives (propagate_by_preintegration).
  std::vector<std::string> step_tasks() const;
  /// Whether the pipeline has a ground-truth source (its steps can be compared).
  bool has_ground_truth() const;
  const PipelineSpec& spec() const { return *spec_; }

 private:
  explicit Pipeline(std::unique_ptr<PipelineSpec> s);
  std::unique_ptr<PipelineSpec> spec_;
};

/// One step of a propagate_by_preintegration task: its prediction and, when it was compared,
/// its errors against the ground truth (for trajectory files: imuconv run --tum, --errors).
struct StepOut {
  const std::string& task;
  std::size_t k;
  std::optional<double> t_end;               ///< seconds on the output's time axis
  std::optional<std::int64_t> t_end_abs_ns;  ///< when the data has an absolute time origin
  const ImuState& x_e;
  std::optional<double> position_error_m, rotation_error_deg, velocity_error_mps;
};

struct RunOptions {
  /// Plugin directories searched before the pipeline's own plugin_dirs (e.g. --plugin-dir).
  std::vector<std::string> plugin_dirs;
  /// Plugin load problems are reported here as warnings (may be null).
  std::ostream* log = nullptr;
  /// The human-readable summary tables are printed here (may be null).
  std::ostream* summary = nullptr;
  /// Called for every step of every propagate_by_preintegration task, in step order (also
  /// with threads), from the thread that writes the output. May be empty.
  std::function<void(const StepOut&)> on_step;
  /// Print every row of a step table; by default a table of more than 50 steps is cut to its
  /// totals and worst steps (the JSON output always has every step).
  bool every_row = false;
  /// Threads for independent intervals (the caller's included): 0 = every core
  /// (std::thread::hardware_concurrency()), 1 = serial. The output does not depend on it:
  /// it is the same, byte for byte, for any number of threads.
  unsigned threads = 0;
  /// Let a plugin override another one's id (the first on the search path wins, with a
  /// warning); without it a duplicate id is an error. The pipeline's "allow_plugin_override"
  /// key does the same. Only for the registry Run/RunToText load themselves.
  bool allow_plugin_override = false;
  /// Load the data and run every check (plugin ids, times, covariances, memory), then stop:
  /// no task runs and the sink receives nothing.
  bool check_only = false;
  /// The per-interval results a task keeps because a later task names it ("measurements":
  /// NAME, convert "source") may take at most this many bytes in all (estimated before any
  /// task runs; ConfigError beyond it). Results no later task names are written and dropped.
  std::size_t max_kept_bytes = std::size_t{1} << 30;
  /// When not null, receives the name of every check task whose verdict is "inconsistent"
  /// (the document is complete all the same; imuconv run then exits 3).
  std::vector<std::string>* inconsistent_checks = nullptr;
  /// Run one shard of the tasks (imuconv run --shard K/N; imuconv merge joins the shards).
  /// The tasks are cut into units, the shortest runs of consecutive tasks that no task's
  /// reference to an earlier one crosses, and shard `index` of `count` runs the contiguous
  /// block of units [index*U/count, (index+1)*U/count) (possibly none). The document is the
  /// whole run's, byte for byte (every check, the data loaded and the head are the same),
  /// with a first member "shard" (the split, and each input file's size and FNV-1a 64 hash)
  /// and only the block's tasks in "tasks".
  struct Shard {
    unsigned index = 0, count = 1;
  };
  std::optional<Shard> shard;
  /// Filled in by the run when not null (for tests and benchmarks).
  struct Stats {
    /// Interval results (measurements, propagations, steps) held for later tasks at the end.
    std::size_t kept_records = 0;
    /// Their size, in bytes, as estimated for max_kept_bytes.
    std::size_t kept_bytes = 0;
    /// Interval results computed and written (kept or not).
    std::size_t records = 0;
  };
  Stats* stats = nullptr;
};

/// Receives the output document's text in order, in pieces.
using TextSink = std::function<void(std::string_view)>;

/// Runs and streams the output document (pretty-printed as PrettyJson lays it out; numbers in
/// the shortest form that reads back exactly) into `sink` while the tasks run, so that a large
/// document never has to be held in memory. The registry is loaded as by Run. On any error
/// the sink has received an incomplete document: write it to a temporary (OutputFile) and
/// discard it on failure.
void RunToText(const Pipeline& p, const RunOptions& options, const TextSink& sink);
void RunToText(const Pipeline& p, const Registry& reg, const RunOptions& options, const TextSink& sink);

/// Loads the registry from RunOptions::plugin_dirs, the pipeline's plugin_dirs and the
/// default search path, then runs. Throws ConfigError / ReadError / Error naming the file.
/// The document is RunToText's text, parsed.
json Run(const Pipeline& p, const RunOptions& options);
/// Runs with a given registry (plugin_dirs of the pipeline and options are then ignored).
json Run(const Pipeline& p, const Registry& reg, const RunOptions& options);

}  // namespace imuconv::pipeline
