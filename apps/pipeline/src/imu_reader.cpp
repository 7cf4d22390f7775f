// The IMU readers: EuRoC and generic CSV, one streaming row loop for both.
#include "imuconv/pipeline/imu_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "data/csv_text.h"
#include "data/line_reader.h"
#include "data/range_keeper.h"
#include "data/read_timing.h"
#include "imuconv/pipeline/errors.h"
#include "imuconv/printable.h"

namespace imuconv::pipeline {

const std::array<const char*, 7> kImuColumnNames = {"t", "wx", "wy", "wz", "ax", "ay", "az"};

namespace {

using data::DelimiterName;
using data::LineReader;
using data::Shown;
using data::ShownBare;
using data::Split;
using data::Trim;

struct Layout {
  std::array<int, 7> index{};        // field index of t, wx, ..., az (each >= 0)
  std::array<std::string, 7> label;  // for messages (escaped)
  std::size_t n_fields = 0;          // fields per line; 0: set by the first data line
  std::size_t header_line = 0;       // the line that fixed n_fields (a header), if any
};

struct RowRules {
  bool integer_time = false;  // EuRoC: integer nanoseconds only
  std::string time_what;      // "an integer timestamp in nanoseconds", for messages
  TimeSource source = TimeSource::imu;
};

// The column with the largest index (the first such), for the width checks.
int WidestColumn(const Layout& layout) {
  return static_cast<int>(std::max_element(layout.index.begin(), layout.index.end()) - layout.index.begin());
}

// The shared streaming core. Every data line must have layout.n_fields fields (once known) and
// every field a column refers to must exist: the width is checked against the header, or
// against the first data line, before any field is indexed.
ImuData ReadImuRows(const std::string& path, const CsvFormat& f, Layout layout, const RowRules& rules,
                    std::optional<TimeValue> origin, LineReader& lr, const ReadOptions& options) {
  const int widest = WidestColumn(layout);
  const auto max_index = static_cast<std::size_t>(layout.index[static_cast<std::size_t>(widest)]);
  if (layout.n_fields > 0 && max_index >= layout.n_fields)
    throw ReadError(path, layout.header_line,
                    "the column map uses index " + std::to_string(max_index) + " (for '" + kImuColumnNames[widest] +
                        "') but the header has " + std::to_string(layout.n_fields) + " columns");
  std::string line;
  std::vector<std::string_view> fields;
  std::optional<TimeValue> first_t;
  TimeOrigin org;
  org.unit = f.time_unit;
  TimeValue prev{};
  double prev_t = 0.0;
  std::size_t prev_line = 0;
  data::RangeKeeper<ImuSample> keeper(options.keep);
  while (lr.next(line)) {
    if (data::IsBlank(line)) continue;
    if (!f.comment.empty() && Trim(line).substr(0, f.comment.size()) == f.comment) continue;
    Split(line, f.delimiter, f.whitespace_delimited, fields);
    const std::size_t ln = lr.line_no();
    if (layout.n_fields == 0) {
      layout.n_fields = fields.size();
      if (fields.size() <= max_index)
        throw ReadError(path, ln,
                        "expected at least " + std::to_string(max_index + 1) + " fields separated by " +
                            DelimiterName(f.delimiter, f.whitespace_delimited) + " (the column map uses index " +
                            std::to_string(max_index) + " for '" + kImuColumnNames[widest] + "'), found " +
                            std::to_string(fields.size()));
    }
    if (fields.size() != layout.n_fields)
      throw ReadError(path, ln,
                      "expected " + std::to_string(layout.n_fields) + " fields separated by " +
                          DelimiterName(f.delimiter, f.whitespace_delimited) + ", found " +
                          std::to_string(fields.size()));
    // From here on fields.size() == n_fields > max_index: every index below is in range.
    ImuSample s;
    const std::string_view tf = fields[static_cast<std::size_t>(layout.index[0])];
    std::optional<TimeValue> tv;
    if (rules.integer_time) {
      std::int64_t ns = 0;
      const std::string_view tt = Trim(tf);
      const auto r = std::from_chars(tt.data(), tt.data() + tt.size(), ns);
      if (!tt.empty() && r.ec == std::errc() && r.ptr == tt.data() + tt.size()) tv = TimeValue{ns, 0.0};
    } else {
      tv = ParseTimeValue(tf);
    }
    if (!tv)
      throw ReadError(path, ln,
                      "column " + std::to_string(layout.index[0]) + " (" + layout.label[0] + "): expected " +
                          rules.time_what + ", found " + Shown(tf));
    if (!first_t) {
      first_t = *tv;
      org.value = origin ? *origin : *tv;
    } else if (!(tv->whole > prev.whole || (tv->whole == prev.whole && tv->frac > prev.frac))) {
      throw ReadError(path, ln,
                      "timestamp " + ShownBare(Trim(tf)) + " is not after the previous sample's (line " +
                          std::to_string(prev_line) + "); timestamps must be strictly increasing");
    }
    prev = *tv;
    s.t = org.relative_seconds(*tv);
    if (prev_line != 0 && !(s.t > prev_t))
      throw ReadError(path, ln, "timestamp is too close to the previous sample's to be told apart in double seconds");
    prev_t = s.t;
    prev_line = ln;
    // Rates and specific forces.
    for (std::size_t k = 1; k < 7; ++k) {
      const std::string_view fv = fields[static_cast<std::size_t>(layout.index[k])];
      const auto v = data::ParseDouble(fv);
      if (!v || !std::isfinite(*v))
        throw ReadError(path, ln,
                        "column " + std::to_string(layout.index[k]) + " (" + layout.label[k] +
                            "): expected a finite number, found " + Shown(fv));
      if (k <= 3)
        s.gyro[static_cast<Eigen::Index>(k - 1)] = *v;
      else
        s.accel[static_cast<Eigen::Index>(k - 4)] = *v;
    }
    keeper.add(s.t, ln, s);
  }
  if (keeper.times().empty()) throw ReadError(path, 0, "contains no IMU samples");
  // The timing checks judge the kept samples only (see data/range_keeper.h).
  data::ThrowIfTimingIssue(path, keeper.times(), keeper.lines(), keeper.window(), options.timing, f.time_unit,
                           rules.source);
  ImuData out;
  out.source = path;
  out.samples = std::move(keeper.rows());
  out.origin = org;
  return out;
}

}  // namespace

ImuData ReadEurocImu(const std::string& path, std::optional<std::int64_t> origin_ns, const ReadOptions& options) {
  LineReader lr(path);
  CsvFormat f;
  f.delimiter = ',';
  f.comment = "#";
  f.time_unit = TimeUnit::ns;
  Layout layout;
  layout.index = {0, 1, 2, 3, 4, 5, 6};
  layout.label = {"timestamp [ns]", "w_x", "w_y", "w_z", "a_x", "a_y", "a_z"};
  layout.n_fields = 7;
  std::optional<TimeValue> origin;
  if (origin_ns) origin = TimeValue{*origin_ns, 0.0};
  return ReadImuRows(path, f, layout, {true, "an integer timestamp in nanoseconds", TimeSource::imu_euroc}, origin, lr,
                     options);
}

namespace {

// "'t', 'gyro_x', ..." for messages: at most the first 20 names (a header line may hold
// hundreds of thousands).
std::string KnownColumns(const std::vector<std::string>& header) {
  constexpr std::size_t kShown = 20;
  std::string known;
  for (std::size_t i = 0; i < header.size() && i < kShown; ++i) known += (i ? ", " : "") + Shown(header[i]);
  if (header.size() > kShown) known += ", ... (" + std::to_string(header.size()) + " columns)";
  return known;
}

}  // namespace

ImuData ReadCsvImu(const std::string& path, const CsvFormat& f, const ReadOptions& options) {
  LineReader lr(path);
  Layout layout;
  std::vector<std::string> header;
  std::string line;
  for (int h = 0; h < f.header_rows; ++h) {
    if (!lr.next(line))
      throw ReadError(path, lr.line_no(), "expected " + std::to_string(f.header_rows) + " header rows, the file ends first");
    if (h == 0) {
      layout.header_line = lr.line_no();
      std::vector<std::string_view> names;
      Split(line, f.delimiter, f.whitespace_delimited, names);
      for (auto n : names) header.emplace_back(Trim(n));
      // A leading comment marker is not part of the first name ("#time" -> "time").
      if (!header.empty() && !f.comment.empty() && header[0].rfind(f.comment, 0) == 0)
        header[0] = std::string(Trim(std::string_view(header[0]).substr(f.comment.size())));
      // The header fixes the width of every data line (a blank header row fixes nothing).
      layout.n_fields = header.size();
    }
  }
  for (std::size_t k = 0; k < 7; ++k) {
    const ColumnRef& c = f.columns[k];
    if (std::holds_alternative<int>(c)) {
      layout.index[k] = std::get<int>(c);
      if (layout.index[k] < 0)
        throw ReadError(path, 0, std::string("column index of '") + kImuColumnNames[k] + "' is negative");
      layout.label[k] = kImuColumnNames[k];
      if (static_cast<std::size_t>(layout.index[k]) < header.size())
        layout.label[k] += ", " + Shown(header[static_cast<std::size_t>(layout.index[k])]);
    } else {
      const std::string& name = std::get<std::string>(c);
      if (f.header_rows == 0)
        throw ReadError(path, 0,
                        std::string("column '") + kImuColumnNames[k] + "' is given by the name " + Quoted(name) +
                            " but the format has no header row (header_rows is 0)");
      const auto it = std::find(header.begin(), header.end(), name);
      if (it == header.end())
        throw ReadError(path, layout.header_line,
                        "no column named " + Quoted(name) + " (for '" + kImuColumnNames[k] + "') in the header; columns: " +
                            (header.empty() ? std::string("none (the header row is blank)") : KnownColumns(header)));
      layout.index[k] = static_cast<int>(it - header.begin());
      layout.label[k] = std::string(kImuColumnNames[k]) + ", " + Quoted(name);
    }
  }
  const RowRules rules{false, std::string("a timestamp in ") + TimeUnitName(f.time_unit), TimeSource::imu};
  return ReadImuRows(path, f, layout, rules, f.time_origin, lr, options);
}

}  // namespace imuconv::pipeline
