// imuconv check's report page (pages.h).
#include "imuconv/check/check.h"
#include "imuconv/report/heatmap.h"
#include "imuconv/report/markup.h"
#include "pages.h"

namespace imuconv::report {
namespace {

const char* Word(check::Verdict v) {
  return v == check::Verdict::consistent ? "consistent" : "inconsistent";
}

std::string Interval(double a, double b) { return Readable(a, 10) + " .. " + Readable(b, 10); }

std::string Joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return "[" + s + "]";
}

// The fixed range of check's entrywise differences d on every heatmap: from double round-off
// (1e-16: two computations of the same numbers agree to about this) to 1e2 (a factor of 100, far
// beyond the 2 a sign error gives), with the tolerance of the matrix kind marked. Anchored, not
// fitted: the same colour means the same d in every report.
AnchoredScale CheckScale(double tolerance) {
  return AnchoredScale::Magnitude(1e-16, 1e2, tolerance);
}

/// A heatmap of one matrix's entrywise d on check's scale, with the tolerance of its kind.
std::string CheckHeatmap(const Eigen::MatrixXd& d, const std::vector<std::string>& rows,
                         const std::vector<std::string>& cols, const std::string& title,
                         double tolerance) {
  HeatmapSpec h;
  h.values = d;
  h.row_blocks = rows;
  h.col_blocks = cols;
  h.title = title;
  h.anchored = CheckScale(tolerance);
  return HeatmapSvg(h);
}

// The verdict's one line: all consistent, or the first inconsistent measurement's first finding.
std::string VerdictReason(const check::CheckResult& r) {
  std::size_t consistent = 0;
  const check::MeasurementCheck* first_bad = nullptr;
  for (const auto& m : r.measurements) {
    if (m.judgement.verdict == check::Verdict::consistent)
      ++consistent;
    else if (!first_bad)
      first_bad = &m;
  }
  std::string s = std::to_string(consistent) + " of " + std::to_string(r.measurements.size()) +
                  " measurements within the tolerances";
  if (first_bad && !first_bad->judgement.findings.empty())
    s += "; measurement " + std::to_string(first_bad->index) + ": " +
         first_bad->judgement.findings.front();
  return s;
}

}  // namespace

HtmlDocument CheckPage(const check::CheckResult& r, const Inputs& inputs) {
  const check::Tolerances& tol = check::CheckTolerances();
  HtmlDocument doc("imuconv check");
  doc.AddVerdict(r.verdict == check::Verdict::consistent, VerdictReason(r));
  doc.AddParagraph(std::string("Verdict: ") + Word(r.verdict) +
                   ". Tolerances on the max of each difference d: " + "increment " +
                   Readable(tol.delta) + ", J_bias " + Readable(tol.J_bias) + ", covariance " +
                   Readable(tol.cov) + " (docs/check.md).");
  std::vector<std::vector<std::string>> input_rows;
  for (const auto& [role, path] : inputs) input_rows.push_back({role, path});
  doc.AddTable({"input", "file"}, input_rows);

  doc.AddHeading(2, "Summary");
  std::vector<std::vector<std::string>> rows;
  for (const auto& m : r.measurements) {
    const check::Explanation& b = m.best;
    rows.push_back(
        {std::to_string(m.index), m.pointer, Interval(m.t_start, m.t_end),
         Word(m.judgement.verdict), b.scheme, b.convention + " " + Joined(b.blocks),
         b.jacobian_convention + " " + Joined(b.J_bias_columns) + (b.J_bias_sign > 0 ? " +" : " -"),
         Readable(b.delta.max, 2), Readable(b.J_bias.max, 2), Readable(b.cov.max, 2)});
  }
  doc.AddTable({"#", "pointer", "interval [s]", "verdict", "scheme", "covariance", "J_bias",
                "max d: increment", "J_bias", "cov"},
               rows);

  for (const auto& m : r.measurements) {
    const check::Explanation& b = m.best;
    doc.AddHeading(2, "Measurement " + std::to_string(m.index) + " (" + m.pointer + "), " +
                          Interval(m.t_start, m.t_end) + " s: " + Word(m.judgement.verdict));
    doc.AddParagraph("Best explanation: scheme " + b.scheme + "; covariance in " + b.convention +
                     " " + Joined(b.blocks) + "; J_bias rows in " + b.jacobian_convention +
                     ", columns " + Joined(b.J_bias_columns) + ", sign " +
                     (b.J_bias_sign > 0 ? "+" : "-") + ".");
    doc.AddList(m.judgement.findings);
    std::vector<HtmlDocument::Figure> figures;
    const check::BestEntries& e = m.best_entries;
    if (e.J_bias.size() == 54 && e.J_bias_rows.size() == 3 && b.J_bias_columns.size() == 2) {
      figures.push_back({CheckHeatmap(e.J_bias, e.J_bias_rows, b.J_bias_columns,
                                      "J_bias: d per entry", tol.J_bias),
                         "Bias Jacobian: |K - U| / max(|K|, 1e-4 max|K|) per entry, K what " +
                             b.scheme + " predicts, U the file's numbers (max " +
                             Readable(b.J_bias.max, 2) + ", mean " + Readable(b.J_bias.mean, 2) +
                             "; tolerance " + Readable(tol.J_bias) + ")."});
    }
    if (e.cov.size() == 225 && b.blocks.size() == 5) {
      figures.push_back(
          {CheckHeatmap(e.cov, b.blocks, b.blocks, "Covariance: d per entry", tol.cov),
           "Covariance on the correlation scale: |K_ij - U_ij| / sqrt(K_ii K_jj) per entry (max " +
               Readable(b.cov.max, 2) + ", mean " + Readable(b.cov.mean, 2) + "; tolerance " +
               Readable(tol.cov) + ")."});
    }
    if (!figures.empty()) doc.AddFigures(figures);
  }
  return doc;
}

}  // namespace imuconv::report
