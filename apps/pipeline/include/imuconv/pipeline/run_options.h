// How a pipeline runs (threads, shards, limits, what is printed) and what it reports while it
// runs (each step): given to Run, RunToText and RunToArrays (pipeline.h), and read by the tasks
// as they run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "imuconv/types.h"

namespace imuconv::pipeline {

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
  /// (the document is complete all the same; imuconv run then exits 1).
  std::vector<std::string>* inconsistent_checks = nullptr;
  /// When not null, receives the name of every optimize task whose solve did not converge (its
  /// document says so, with no covariances; imuconv run then exits 1, as imuconv optimize does).
  std::vector<std::string>* unconverged_solves = nullptr;
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

}  // namespace imuconv::pipeline
