// The residual task's ResidualSink (residual_factor.h): what a residual plugin writes goes
// straight into the task's JSON (or NPZ events) under the plugin's names, vectors as one-line
// arrays and matrices as arrays of rows, so the output has the layout the plugin chose. The
// plugin is hostile until shown otherwise: every name, size and number is checked here, and
// the first problem is kept (with the output pointer it concerns) for the task to report
// after evaluate() returns; nothing is thrown back into the plugin.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "imuconv/pipeline/json_writer.h"
#include "imuconv/residual_factor.h"

namespace imuconv::pipeline {

class ResidualJsonSink final : public ResidualSink {
 public:
  /// Numbers one evaluation may write: far above a system's factor (VINS-Fusion's 1,260,
  /// OKVIS2's 2,000), low enough that a runaway plugin cannot exhaust memory.
  static constexpr long long kMaxNumbers = 1 << 20;

  /// Writes into the object `w` has open.
  explicit ResidualJsonSink(JsonWriter& w) : w_(w) { names_.emplace_back(); }

  void begin_group(const char* name) noexcept override;
  void end_group() noexcept override;
  void vector(const char* name, const double* values, int size) noexcept override;
  void matrix(const char* name, const double* row_major, int rows, int cols) noexcept override;
  void mahalanobis_squared(double value) noexcept override;

  /// After evaluate(): the first problem ("" if none), e.g. an unclosed group.
  std::string problem() const;
  const std::optional<double>& distance() const { return distance_; }

 private:
  /// Whether `name` may be written in the open group (records the problem if not).
  bool take_name(const char* name) noexcept;
  bool take_size(const char* name, long long rows, long long cols) noexcept;
  void record(std::string message) noexcept;

  JsonWriter& w_;
  std::vector<std::set<std::string>> names_;  // names written, per open group
  long long numbers_ = 0;
  std::optional<double> distance_;
  std::string problem_;
};

}  // namespace imuconv::pipeline
