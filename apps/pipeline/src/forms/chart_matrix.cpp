// The chart-matrix forms, read and written (json_io.h, chart_matrix.h).
#include "chart_matrix.h"

#include <tuple>

#include "../io/message_text.h"
#include "imuconv/pipeline/json_parse.h"
#include "input_checks.h"

namespace imuconv::pipeline {

json MixedMatrixToJson(const Eigen::MatrixXd& m, const std::string& row_convention,
                       const std::vector<std::string>& row_blocks,
                       const std::string& col_convention,
                       const std::vector<std::string>& col_blocks) {
  return {{"rows", {{"convention", row_convention}, {"blocks", row_blocks}}},
          {"cols", {{"convention", col_convention}, {"blocks", col_blocks}}},
          {"matrix", MatrixToJson(m)}};
}

void WriteChartKeys(JsonWriter& w, const std::string& convention,
                    const std::vector<std::string>& blocks) {
  w.key("convention");
  w.string(convention);
  w.key("blocks");
  w.string_list(blocks);
}

void WriteMixedCharts(JsonWriter& w, const std::string& row_convention,
                      const std::vector<std::string>& row_blocks, const std::string& col_convention,
                      const std::vector<std::string>& col_blocks) {
  for (auto [k, c, b] :
       {std::tuple<const char*, const std::string*, const std::vector<std::string>*>{
            "rows", &row_convention, &row_blocks},
        {"cols", &col_convention, &col_blocks}}) {
    w.key(k);
    w.begin_object();
    WriteChartKeys(w, *c, *b);
    w.end_object();
  }
}

void WriteCovariance(JsonWriter& w, const Mat15& m, const std::string& convention,
                     const std::vector<std::string>& blocks) {
  CheckOutputCovariance(m, w.pointer() + "/matrix");
  WriteChart(w, m, convention, blocks);
}

std::vector<std::string> Blocks(const Registry& reg, PluginKind kind, const std::string& id) {
  return reg.info(kind, id).blocks;
}

std::optional<Matrix15In> Matrix15FromJson(const Node& n) {
  Matrix15In out;
  out.pointer = n.pointer();
  const std::size_t before = n.checker().count();
  if (n.is_array()) {
    if (auto m = n.matrix(15, 15)) out.m = *m;
  } else if (n.is_object() && n.has("diagonal")) {
    n.expect_object({"diagonal", "convention", "blocks"});
    if (auto d = n["diagonal"].vector(15)) out.m = d->asDiagonal();
  } else if (n.is_object() && n.has("sigma")) {
    n.expect_object({"sigma", "convention", "blocks"});
    if (auto d = n["sigma"].vector(15)) {
      // A standard deviation is not negative: squared in silence, a sign slip (or a row of
      // something else) would pass as a covariance.
      for (int i = 0; i < 15; ++i)
        if ((*d)[i] < 0.0)
          n["sigma"].fail("entry " + std::to_string(i) + " is " + Num((*d)[i]) +
                          ": a standard deviation is not negative");
      out.m = d->cwiseAbs2().asDiagonal();
    }
  } else if (n.is_object()) {
    n.expect_object({"matrix", "convention", "blocks"});
    if (auto mn = n.get("matrix", true))
      if (auto m = mn->matrix(15, 15)) out.m = *m;
  } else {
    n.fail(
        "expected a 15x15 matrix (an array of 15 rows), {\"diagonal\": [15 numbers]}, {\"sigma\": "
        "[15 numbers]} or {\"convention\", \"blocks\", \"matrix\"}; found " +
        TypeName(n.value()));
    return std::nullopt;
  }
  if (n.is_object()) {
    if (auto c = n.string("convention", false)) out.convention = *c;
    if (auto b = n.get("blocks", false)) {
      auto labels = b->string_list();
      if (labels && labels->size() != 5)
        b->fail("expected 5 block labels");
      else if (labels)
        out.blocks = *labels;
    }
  }
  if (n.checker().count() != before) return std::nullopt;
  if (!out.m.allFinite()) {
    n.fail("matrix has non-finite entries");
    return std::nullopt;
  }
  return out;
}

Matrix15In ReadMatrixFile(const std::string& path, bool covariance) {
  return ReadJsonFileAs(path, [covariance](const Node& n) {
    auto m = Matrix15FromJson(n);
    if (m && covariance && !CheckCovarianceInput(n.checker(), m->pointer, m->m)) m.reset();
    return m;
  });
}

}  // namespace imuconv::pipeline
