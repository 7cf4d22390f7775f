// The chart-matrix forms: every matrix imuconv writes carries its chart(s).
//   {"convention", "blocks", "matrix"}                                  one chart
//   {"rows": {"convention", "blocks"}, "cols": {...}, "matrix"}         two (a Jacobian)
//   {"convention", "blocks", "vector"}                                  a vector in a chart
// The streaming writers are here; the reader (Matrix15FromJson) and the json value forms are
// declared in json_io.h. All are implemented in chart_matrix.cpp, side by side.
#pragma once

#include <string>
#include <vector>

#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/json_writer.h"

namespace imuconv::pipeline {

/// The "convention" and "blocks" keys that name a chart, inside the object the caller opened:
/// every chart-matrix form above writes its chart(s) through this.
void WriteChartKeys(JsonWriter& w, const std::string& convention,
                    const std::vector<std::string>& blocks);

/// {"convention", "blocks", key}: one value in one chart, written by write_value().
template <typename WriteValue>
void WriteInChart(JsonWriter& w, const std::string& convention,
                  const std::vector<std::string>& blocks, const char* key,
                  const WriteValue& write_value) {
  w.begin_object();
  WriteChartKeys(w, convention, blocks);
  w.key(key);
  write_value();
  w.end_object();
}

/// {"convention", "blocks", "matrix"}.
template <typename M>
void WriteChart(JsonWriter& w, const M& m, const std::string& convention,
                const std::vector<std::string>& blocks) {
  WriteInChart(w, convention, blocks, "matrix", [&] { w.matrix(m); });
}

/// {"convention", "blocks", "vector"}.
template <typename V>
void WriteChartVector(JsonWriter& w, const V& v, const std::string& convention,
                      const std::vector<std::string>& blocks) {
  WriteInChart(w, convention, blocks, "vector", [&] { w.vector(v); });
}

/// The "rows" and "cols" keys of a two-chart matrix (WriteMixed without the matrix).
void WriteMixedCharts(JsonWriter& w, const std::string& row_convention,
                      const std::vector<std::string>& row_blocks, const std::string& col_convention,
                      const std::vector<std::string>& col_blocks);

/// {"rows": {"convention", "blocks"}, "cols": {...}, "matrix"}.
template <typename M>
void WriteMixed(JsonWriter& w, const M& m, const std::string& row_convention,
                const std::vector<std::string>& row_blocks, const std::string& col_convention,
                const std::vector<std::string>& col_blocks) {
  w.begin_object();
  WriteMixedCharts(w, row_convention, row_blocks, col_convention, col_blocks);
  w.key("matrix");
  w.matrix(m);
  w.end_object();
}

/// A covariance the pipeline computed, in one chart: checked first (CheckOutputCovariance:
/// a negative variance is a defect to report, never written), then written.
void WriteCovariance(JsonWriter& w, const Mat15& m, const std::string& convention,
                     const std::vector<std::string>& blocks);

}  // namespace imuconv::pipeline
