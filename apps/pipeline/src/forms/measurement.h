// The measurement form: one preintegrated measurement with its times, bias estimate, increment,
// bias Jacobian and covariance, in preint_reference and in any registered increment
// convention. The reader takes measurements files (schemas/measurements.schema.json), e.g.
// numbers dumped from GTSAM, into the reference charts with FromConvention; the writer gives
// a preintegrate task's measurements in the same form (internal to imuconv_pipeline).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "imuconv/bridge.h"
#include "imuconv/pipeline/json_check.h"
#include "imuconv/pipeline/json_writer.h"
#include "task_common.h"

namespace imuconv::pipeline {

/// A measurement with its time span (when known) and where it came from.
struct MeasRecord {
  Preintegrated m;
  std::optional<double> t_s, t_e;
  std::size_t n_knots = 0;
  std::string pointer;  // where it came from, for messages ("" for task outputs)
  // Files: the charts the measurement was given in (for the output's plugin provenance).
  std::string convention, jacobian_convention;
};

/// Reads and checks a measurements file: every problem is reported with the file and its
/// JSON pointer (ConfigError; ReadError when it cannot be opened). `origin_ns` is the time
/// origin of the pipeline's IMU data: t_start/t_end (or *_abs_ns) are put on that axis.
/// Checked, never repaired: unit quaternions (1e-6), rotation matrices, R and q_wxyz and
/// rotation_angle_deg agreeing when several are given, t_start and t_start_abs_ns agreeing
/// (1e-6 s), dt = t_end - t_start (1e-6 s), and the covariance (symmetric and positive
/// semi-definite, CovarianceInputProblem).
std::vector<MeasRecord> ReadMeasurementFile(const std::string& path, const Registry& reg,
                                            std::optional<std::int64_t> origin_ns);
/// The same from a parsed document; `file` names it in messages.
std::vector<MeasRecord> ReadMeasurementDocument(const json& doc, const std::string& file, const Registry& reg,
                                                std::optional<std::int64_t> origin_ns);

/// Writes measurement `k`: index, times, dt, n_knots, bias_estimate, delta, then J_bias and
/// cov in preint_reference and "expressed" in each of `conventions`, less what `omit` leaves
/// out. Computed covariances are checked before they are written (WriteCovariance).
void WriteMeasurement(JsonWriter& w, const MeasRecord& r, std::size_t k, const std::vector<std::string>& conventions,
                      const Registry& reg, const OmitSpec& omit, const std::optional<TimeOrigin>& origin);

}  // namespace imuconv::pipeline
