// imuconv montecarlo: its options and its run, apart from the command line (cmd_montecarlo.cpp
// maps the flags onto MontecarloCommandOptions), so that a test can run the command without
// CLI11.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "imuconv/cli/commands.h"

namespace imuconv::cli {

/// An option left empty was not given: a merge takes none of the run's options, and its
/// refusal names the first given.
struct MontecarloCommandOptions {
  // A run, or a shard of one.
  std::optional<std::string> case_path;      ///< --case CASE.json, or
  std::optional<std::string> pipeline_path;  ///< --pipeline P.json (zero bias estimate)
  std::optional<double> from, to;     ///< --from, --to: the interval (default: all the samples)
  std::optional<std::string> method;  ///< --method: a propagator or a preintegrator id
  std::optional<int> trials;          ///< --trials N
  std::optional<std::uint64_t> seed;  ///< --seed S
  std::optional<std::string> shard;   ///< --shard K/N, as given
  std::optional<std::string> shard_output;  ///< -o FILE: the shard file
  std::optional<std::string>
      convention;                     ///< --convention: the increment convention of the end error
  std::optional<int> threads;         ///< --threads (default: every core)
  std::optional<double> duration;     ///< --duration SECONDS from the interval's start
  std::optional<double> noise_scale;  ///< --noise-scale (hidden): the simulated densities only
  // A merge.
  std::vector<std::string> merge_files;  ///< --merge SHARD...
  // Every form but a shard.
  bool as_json = false;     ///< --json: one JSON object instead of the summary
  std::string report_path;  ///< --report OUT.html, or empty
};

/// Runs the trials (or a shard of them, or merges shards), prints the summary or JSON on stdout
/// (a shard: its "wrote" line) and returns the exit code: 0 consistent (or a shard written), 1
/// inconsistent, 2 unusable input or options, 3 internal error (exit_codes.h).
[[nodiscard]] int RunMontecarloCommand(const CommandContext& ctx,
                                       const MontecarloCommandOptions& o);

}  // namespace imuconv::cli
