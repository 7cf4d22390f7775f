// imuconv check, as a library: each measurement of a measurements file against the reference
// schemes over a reference case's samples (references.h), explained (explain.h) and judged
// (verdict.h). The command line is apps/cmd_check.cpp; the output forms are report.h.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "imuconv/check/case_input.h"
#include "imuconv/check/explain.h"
#include "imuconv/check/verdict.h"

namespace imuconv::pipeline {
struct DeclaredMeasurement;
}

namespace imuconv::check {

/// The entrywise differences under the best explanation (difference.h, entry by entry): what
/// the HTML report's heatmaps draw. Their max and mean are best.J_bias and best.cov.
struct BestEntries {
  Eigen::MatrixXd J_bias;                // 9x6: rows J_bias_rows, columns best.J_bias_columns
  std::vector<std::string> J_bias_rows;  // the row chart's theta, p, v blocks, in its order
  Eigen::MatrixXd cov;                   // 15x15: rows and columns best.blocks
};

struct MeasurementCheck {
  std::size_t index = 0;
  std::string pointer;
  double t_start = 0.0, t_end = 0.0;
  double sample_period = 0.0;  // median over the interval's samples: what "x1/dt" is said of
  bool float32 = false, float32_inferred = true;  // the precision of the numbers (NumberPrecision)
  /// dt as written minus t_end - t_start, when they differ (DtDifference), and the most a sum
  /// of the interval's steps in the numbers' precision can differ by (check.cpp).
  std::optional<double> dt_difference;
  double dt_rounding_bound = 0.0;
  Constraints declared;  // J_bias_sign is +1: a measurements file holds d/d(bias estimate)
  bool jacobian_convention_implied = false;
  Explanation under_declaration, best;
  BestEntries best_entries;
  Judgement judgement;
  /// The schemes that could not run on this interval, each with the reason; the judgment is
  /// made with the others.
  std::vector<std::pair<std::string, std::string>> not_applicable;
};

struct CheckResult {
  Verdict verdict = Verdict::consistent;
  std::vector<MeasurementCheck> measurements;
};

/// Checks every measurement. Throws pipeline::ConfigError naming `measurements_file` and the
/// measurement's pointer when its interval is not inside the case's samples.
CheckResult RunCheck(const Registry& reg, const CaseInput& input,
                     const std::vector<pipeline::DeclaredMeasurement>& ms,
                     const std::string& measurements_file);

}  // namespace imuconv::check
