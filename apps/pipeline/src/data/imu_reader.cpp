// The IMU readers: EuRoC and generic CSV, one streaming row loop for both.
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/imu_plausibility.h"

#include <algorithm>

#include "csv_text.h"
#include "imuconv/pipeline/errors.h"
#include "imuconv/printable.h"
#include "row_loop.h"

namespace imuconv::pipeline {

const std::array<const char*, 7> kImuColumnNames = {"t", "wx", "wy", "wz", "ax", "ay", "az"};

namespace {

using data::Shown;
using data::Split;
using data::Trim;

struct ImuLayout {
  std::array<int, 7> index{};        // field index of t, wx, ..., az (each >= 0)
  std::array<std::string, 7> label;  // for messages (escaped)
  std::size_t n_fields = 0;          // fields per line; 0: set by the first data line
  std::size_t header_line = 0;       // the line that fixed n_fields (a header), if any
};

// The column with the largest index (the first such), for the width checks.
int WidestColumn(const ImuLayout& layout) {
  return static_cast<int>(std::max_element(layout.index.begin(), layout.index.end()) -
                          layout.index.begin());
}

// Every data line must have layout.n_fields fields (once known) and every field a column
// refers to must exist: the width is checked against the header here, or against the first
// data line by the row loop, before any field is indexed.
ImuData ReadImuRows(const std::string& path, data::RowFormat rf, const ImuLayout& layout,
                    std::optional<TimeValue> origin, data::LineReader& lr,
                    const ReadOptions& options) {
  const int widest = WidestColumn(layout);
  const auto max_index = static_cast<std::size_t>(layout.index[static_cast<std::size_t>(widest)]);
  const std::string uses =
      "index " + std::to_string(max_index) + " (for '" + kImuColumnNames[widest] + "')";
  if (layout.n_fields > 0 && max_index >= layout.n_fields)
    throw ReadError(path, layout.header_line,
                    "the column map uses " + uses + " but the header has " +
                        std::to_string(layout.n_fields) + " columns");
  rf.n_fields = layout.n_fields;
  rf.min_fields = max_index + 1;
  rf.min_fields_why = " (the column map uses index " + std::to_string(max_index) + " for '" +
                      kImuColumnNames[widest] + "')";
  rf.time_index = static_cast<std::size_t>(layout.index[0]);
  rf.time_label = layout.label[0];
  std::optional<TimeOrigin> org;
  if (origin) org = TimeOrigin{*origin, rf.unit};
  data::RowLoop loop(path, lr, std::move(rf), org);
  auto kept = data::ReadRows<ImuSample>(loop, options, [&layout](const data::RowLoop& row) {
    ImuSample s;
    s.t = row.t();
    for (std::size_t k = 1; k < 7; ++k) {
      const double v = row.number(static_cast<std::size_t>(layout.index[k]), layout.label[k]);
      if (k <= 3)
        s.gyro[static_cast<Eigen::Index>(k - 1)] = v;
      else
        s.accel[static_cast<Eigen::Index>(k - 4)] = v;
    }
    return s;
  });
  ImuData out;
  out.source = path;
  out.samples = std::move(kept.rows());
  out.origin = loop.origin();
  out.warnings = ImuPlausibilityWarnings(out.samples, path);
  return out;
}

data::RowFormat CsvRows(const CsvFormat& f) {
  data::RowFormat rf;
  rf.delimiter = f.delimiter;
  rf.whitespace_delimited = f.whitespace_delimited;
  rf.comment = f.comment;
  rf.time_what = std::string("a timestamp in ") + TimeUnitName(f.time_unit);
  rf.unit = f.time_unit;
  return rf;
}

}  // namespace

ImuData ReadEurocImu(const std::string& path, std::optional<std::int64_t> origin_ns,
                     const ReadOptions& options) {
  data::LineReader lr(path);
  CsvFormat f;
  f.comment = "#";
  f.time_unit = TimeUnit::ns;
  data::RowFormat rf = CsvRows(f);
  rf.integer_time = true;
  rf.time_what = "an integer timestamp in nanoseconds";
  rf.source = TimeSource::imu_euroc;
  ImuLayout layout;
  layout.index = {0, 1, 2, 3, 4, 5, 6};
  layout.label = {"timestamp [ns]", "w_x", "w_y", "w_z", "a_x", "a_y", "a_z"};
  layout.n_fields = 7;
  std::optional<TimeValue> origin;
  if (origin_ns) origin = TimeValue{*origin_ns, 0.0};
  return ReadImuRows(path, std::move(rf), layout, origin, lr, options);
}

namespace {

// "'t', 'gyro_x', ..." for messages: at most the first 20 names (a header line may hold
// hundreds of thousands).
std::string KnownColumns(const std::vector<std::string>& header) {
  constexpr std::size_t kShown = 20;
  std::string known;
  for (std::size_t i = 0; i < header.size() && i < kShown; ++i)
    known += (i ? ", " : "") + Shown(header[i]);
  if (header.size() > kShown) known += ", ... (" + std::to_string(header.size()) + " columns)";
  return known;
}

}  // namespace

ImuData ReadCsvImu(const std::string& path, const CsvFormat& f, const ReadOptions& options) {
  data::LineReader lr(path);
  ImuLayout layout;
  std::vector<std::string> header;
  std::string line;
  for (int h = 0; h < f.header_rows; ++h) {
    if (!lr.next(line))
      throw ReadError(
          path, lr.line_no(),
          "expected " + std::to_string(f.header_rows) + " header rows, the file ends first");
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
        throw ReadError(path, 0,
                        std::string("column index of '") + kImuColumnNames[k] + "' is negative");
      layout.label[k] = kImuColumnNames[k];
      if (static_cast<std::size_t>(layout.index[k]) < header.size())
        layout.label[k] += ", " + Shown(header[static_cast<std::size_t>(layout.index[k])]);
    } else {
      const std::string& name = std::get<std::string>(c);
      if (f.header_rows == 0)
        throw ReadError(path, 0,
                        std::string("column '") + kImuColumnNames[k] + "' is given by the name " +
                            Quoted(name) + " but the format has no header row (header_rows is 0)");
      const auto it = std::find(header.begin(), header.end(), name);
      if (it == header.end())
        throw ReadError(path, layout.header_line,
                        "no column named " + Quoted(name) + " (for '" + kImuColumnNames[k] +
                            "') in the header; columns: " +
                            (header.empty() ? std::string("none (the header row is blank)")
                                            : KnownColumns(header)));
      // A name the header holds twice does not say which column is meant.
      const auto again = std::find(it + 1, header.end(), name);
      if (again != header.end())
        throw ReadError(path, layout.header_line,
                        "the header names " + Shown(name) + " twice (columns " +
                            std::to_string(it - header.begin()) + " and " +
                            std::to_string(again - header.begin()) + "), so the column for '" +
                            kImuColumnNames[k] + "' is ambiguous; give its index instead");
      layout.index[k] = static_cast<int>(it - header.begin());
      layout.label[k] = std::string(kImuColumnNames[k]) + ", " + Quoted(name);
    }
  }
  // Each quantity has its own column (the pipeline's parser refuses two equal entries of the
  // map; a name and an index can still meet here, where the header is known).
  for (std::size_t k = 1; k < 7; ++k)
    for (std::size_t j = 0; j < k; ++j)
      if (layout.index[j] == layout.index[k])
        throw ReadError(path, layout.header_line,
                        "the column map reads column " + std::to_string(layout.index[k]) +
                            " for both '" + kImuColumnNames[j] + "' and '" + kImuColumnNames[k] +
                            "' (" + layout.label[j] + "; " + layout.label[k] +
                            "); each of t, wx, wy, wz, ax, ay, az needs its own column");
  return ReadImuRows(path, CsvRows(f), layout, f.time_origin, lr, options);
}

}  // namespace imuconv::pipeline
