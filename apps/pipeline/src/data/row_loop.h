// The one row loop of the CSV-like readers (IMU files of either format, ground truth).
//
// RowLoop does what every row of such a file needs, in one place: reads the lines, skips
// blank and comment lines, splits the fields and checks their count, parses the timestamp,
// checks that the times increase strictly (also after the conversion to double seconds
// relative to the origin) and reports every problem as ReadError with the file and line.
// ReadRows then feeds the rows through RangeKeeper (the keep range) and applies the timing
// checks (read_timing.h) to what was kept. A reader supplies the format and turns the fields
// of one row into its value.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/imu_reader.h"
#include "line_reader.h"
#include "range_keeper.h"
#include "read_timing.h"

namespace imuconv::pipeline::data {

struct RowFormat {
  char delimiter = ',';
  bool whitespace_delimited = false;
  std::string comment;  ///< lines starting with this (after blanks) are skipped; "" = none
  /// Fields per row; 0: as many as the first data row has (which must be at least
  /// min_fields, `min_fields_why` saying why, e.g. " (the column map uses index 7 for 'az')").
  std::size_t n_fields = 0;
  std::size_t min_fields = 0;
  std::string min_fields_why;
  /// What the fields are, after "expected 17 fields" (e.g. " (timestamp [ns], p xyz, ...)").
  std::string fields_what;
  std::size_t time_index = 0;
  std::string time_label;       ///< "timestamp [ns]", "t, 'time'"
  bool integer_time = false;    ///< integers only (nanosecond stamps)
  std::string time_what;        ///< "an integer timestamp in nanoseconds", for messages
  TimeUnit unit = TimeUnit::s;  ///< of the stamps in the file
  TimeSource source = TimeSource::imu;
  const char* row_noun = "sample";                ///< "the previous sample's"
  const char* empty = "contains no IMU samples";  ///< the message for a file without rows
};

class RowLoop {
 public:
  /// Times are made relative to `origin`, in any unit (ground truth in ns on an IMU axis in
  /// s, or in s on an axis in ns: the difference is taken exactly either way); with no origin, the
  /// first row's time is the origin, in the file's unit.
  RowLoop(std::string path, LineReader& lines, RowFormat format, std::optional<TimeOrigin> origin);

  /// Moves to the next data row; false at the end of the file.
  bool next();
  const std::vector<std::string_view>& fields() const noexcept { return fields_; }
  std::size_t line() const noexcept { return line_no_; }
  /// Seconds relative to the origin.
  double t() const noexcept { return t_; }
  /// The origin used (after the first row, when it came from the first row).
  const TimeOrigin& origin() const noexcept { return origin_; }
  const std::string& path() const noexcept { return path_; }
  const RowFormat& format() const noexcept { return f_; }

  /// Field `index` as a finite number, or ReadError "column 3 (w_z): expected a finite
  /// number, found 'x'" at this line.
  double number(std::size_t index, const std::string& label) const;
  [[noreturn]] void fail(const std::string& message) const;

 private:
  TimeValue parse_time() const;
  double relative(const TimeValue& tv) const;

  std::string path_;
  LineReader& lines_;
  RowFormat f_;
  bool have_origin_;
  TimeOrigin origin_;
  std::string delimited_;  // " separated by ','", for messages
  std::string line_;
  std::vector<std::string_view> fields_;
  std::size_t line_no_ = 0;
  double t_ = 0.0;
  TimeValue prev_{};
  std::size_t prev_line_ = 0;
};

/// Every row of `loop`, each turned into a Row by make_row(loop), kept as options.keep says;
/// then the timing checks on the kept rows. Throws ReadError (file and line) on any problem.
template <typename Row, typename MakeRow>
RangeKeeper<Row> ReadRows(RowLoop& loop, const ReadOptions& options, MakeRow make_row) {
  RangeKeeper<Row> keeper(options.keep);
  while (loop.next()) keeper.add(loop.t(), loop.line(), make_row(loop));
  if (keeper.times().empty()) throw ReadError(loop.path(), 0, loop.format().empty);
  ThrowIfTimingIssue(loop.path(), keeper.times(), keeper.lines(), keeper.window(), options.timing,
                     loop.format().unit, loop.format().source);
  return keeper;
}

}  // namespace imuconv::pipeline::data
