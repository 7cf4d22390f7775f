// imuconv experiment: its options and its run, apart from the command line (cmd_experiment.cpp
// maps the flags onto ExperimentCommandOptions), so that a test can run the command without
// CLI11.
#pragma once

#include <cstdint>
#include <string>

#include "imuconv/cli/commands.h"

namespace imuconv::cli {

struct ExperimentCommandOptions {
  std::string which;               ///< EXPERIMENT: preint-by-prop, prop-by-preint or both
  int trials = 100;                ///< --trials (the note's 100)
  std::uint64_t seed = 0;          ///< --seed
  int threads = 0;                 ///< --threads; 0: every core
  double rate = 200.0;             ///< --rate in Hz (the note's 200)
  double duration = 10.0;          ///< --duration of a trial in seconds (the note's 10)
  std::string propagator = "rk4";  ///< --propagator (the note's rk4)
  std::string input = "mid";       ///< --input: mid or zoh, what the preintegrators are fed
  int propagator_substeps = 1;     ///< --propagator-substeps
  bool as_json = false;            ///< --json: one JSON object instead of the summary
  std::string report_path;         ///< --report OUT.html, or empty
};

/// Runs the experiments, prints the summary or JSON on stdout and returns the exit code: 0
/// done, 2 unusable options or a failed trial, 3 internal error (exit_codes.h).
[[nodiscard]] int RunExperimentCommand(const CommandContext& ctx,
                                       const ExperimentCommandOptions& o);

}  // namespace imuconv::cli
