// imuconv check: its options and its run, apart from the command line (cmd_check.cpp maps the
// flags onto CheckCommandOptions), so that a test can run the command without CLI11.
#pragma once

#include <string>

#include "imuconv/cli/commands.h"

namespace imuconv::cli {

struct CheckCommandOptions {
  std::string measurements;   ///< MEAS: the measurements file (schemas/measurements.schema.json)
  std::string case_path;      ///< --case: the IMU samples and noise, or
  std::string pipeline_path;  ///< --pipeline: a pipeline's /imu and /noise (exactly one of the two)
  bool as_json = false;       ///< --json: one JSON object instead of the table
  std::string report_path;    ///< --report OUT.html, or empty
};

/// Checks the measurements, prints the table or JSON on stdout and returns the exit code: 0
/// consistent, 1 inconsistent, 2 unusable input, 3 internal error (exit_codes.h). Throws
/// UsageError when neither or both of --case and --pipeline are given.
[[nodiscard]] int RunCheckCommand(const CommandContext& ctx, const CheckCommandOptions& o);

}  // namespace imuconv::cli
