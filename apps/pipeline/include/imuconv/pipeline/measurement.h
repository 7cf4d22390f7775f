// The measurement form: one preintegrated measurement with its times, bias estimate, increment,
// bias Jacobian and covariance, in preint_reference and in any registered increment
// convention. The reader takes measurements files (schemas/measurements.schema.json), e.g.
// numbers dumped from GTSAM, into the reference charts with FromConvention; the writer gives
// a preintegrate task's measurements in the same form. Read by imuconv check and the Python
// module too (src/forms/measurement.cpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "imuconv/bridge.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/json_check.h"
#include "imuconv/pipeline/json_writer.h"
#include "imuconv/pipeline/omit.h"

namespace imuconv::pipeline {

/// A measurement with its time span (when known) and where it came from.
/// The precision a measurement's numbers carry: its "precision" ("float64" or "float32"), or
/// when it has none float32 if every number of delta, J_bias and cov is a float32 value (a
/// double that single precision rounds to itself: what a float dump holds), else float64.
/// Numbers in float32 have their covariance judged at kCovarianceTolFloat32 (input_checks.h).
struct NumberPrecision {
  bool float32 = false;
  bool inferred = true;  // not written in the file
};

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
/// semi-definite, CovarianceInputProblem, at the precision the numbers carry: NumberPrecision).
std::vector<MeasRecord> ReadMeasurementFile(const std::string& path, const Registry& reg,
                                            std::optional<std::int64_t> origin_ns);
/// The same from a parsed document; `file` names it in messages.
std::vector<MeasRecord> ReadMeasurementDocument(const json& doc, const std::string& file,
                                                const Registry& reg,
                                                std::optional<std::int64_t> origin_ns);

/// A measurement as a file declares it, before anything is assumed about its charts: what
/// `imuconv check` reads (apps/check). Each declaration may be missing or "unknown" (then
/// empty here); the matrices are kept as written, in whatever charts and orders they are.
struct DeclaredMeasurement {
  std::string pointer;  // "/measurements/<i>", for messages
  std::optional<double> t_s, t_e;
  Preintegrated in;  // in.convention / in.jacobian_convention: as declared ("" = not declared)
  std::vector<std::string>
      cov_blocks;  // the declared order of the five blocks of cov ({} = not declared)
  std::vector<std::string> J_bias_rows;  // the declared row blocks of J_bias ({} = not declared)
  std::vector<std::string>
      J_bias_cols;  // the declared column order of J_bias, e.g. {"ba", "bg"} ({} = not declared)
  bool jacobian_convention_implied =
      false;  // the J_bias chart is the one the cov convention implies, not written
  // "unknown" written for cov.blocks / J_bias cols.blocks. A missing order, by contrast, means
  // the chart's own order when the chart is declared (as ReadMeasurementFile takes it).
  bool cov_blocks_unknown = false, J_bias_cols_unknown = false;
  NumberPrecision precision;
  // dt as written (in.dt) may differ from t_end - t_start: check reports it as a finding
  // (DtDifference), not as an error.
};

/// in.dt - (t_end - t_start), when both are known and differ by more than a time's rounding
/// (1e-6 s, as the measurements form compares two statements of one time).
std::optional<double> DtDifference(const DeclaredMeasurement& m);

/// Reads a measurements file as ReadMeasurementFile does (same envelope, times, dt, bias
/// estimate, increment and the same checks of the covariance), except that `cov.convention`,
/// `cov.blocks`, J_bias's chart (`convention`, `rows.convention`, `cols.convention`) and its
/// column order (`cols.blocks`) may be missing or "unknown", and that declared block orders
/// need only be orderings of the labels (the check says whether they are right). t_start and
/// t_end are taken as written, in seconds on the file's own axis (a reference case's axis),
/// unless `origin_ns` is given: then they are put on that pipeline's time axis as
/// ReadMeasurementFile puts them (imuconv check --pipeline, the check task).
/// Problems are reported as ReadMeasurementFile reports them (ConfigError with pointers).
std::vector<DeclaredMeasurement> ReadDeclaredMeasurementFile(
    const std::string& path, const Registry& reg,
    std::optional<std::int64_t> origin_ns = std::nullopt);
/// The same from a parsed document (the Python module's measurements given as values);
/// `file` names it in messages.
std::vector<DeclaredMeasurement> ReadDeclaredMeasurementDocument(
    const json& doc, const std::string& file, const Registry& reg,
    std::optional<std::int64_t> origin_ns = std::nullopt);

/// Writes measurement `k`: index, times, dt, n_knots, bias_estimate, delta, then J_bias and
/// cov in preint_reference and "expressed" in each of `conventions`, less what `omit` leaves
/// out. Computed covariances are checked before they are written (WriteCovariance).
void WriteMeasurement(JsonWriter& w, const MeasRecord& r, std::size_t k,
                      const std::vector<std::string>& conventions, const Registry& reg,
                      const OmitSpec& omit, const std::optional<TimeOrigin>& origin);

}  // namespace imuconv::pipeline
