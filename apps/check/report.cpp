#include "imuconv/check/report.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace imuconv::check {
namespace {

using json = nlohmann::json;

const char* Word(Verdict v) { return v == Verdict::consistent ? "consistent" : "inconsistent"; }

json OrUnknown(const std::string& s) { return s.empty() ? json("unknown") : json(s); }
json OrUnknown(const std::vector<std::string>& v) { return v.empty() ? json("unknown") : json(v); }

// JSON has no infinity: a difference that is not finite (a non-finite user entry) is written
// as null.
json Number(double d) { return std::isfinite(d) ? json(d) : json(nullptr); }

json Diff(const EntryDiff& d) { return {{"max_d", Number(d.max)}, {"mean_d", Number(d.mean)}}; }

json ExplanationJson(const Explanation& e) {
  return {{"scheme", e.scheme},
          {"convention", e.convention},
          {"blocks", e.blocks},
          {"jacobian_convention", e.jacobian_convention},
          {"J_bias_columns", e.J_bias_columns},
          {"J_bias_sign", e.J_bias_sign},
          {"delta", Diff(e.delta)},
          {"J_bias", Diff(e.J_bias)},
          {"cov", Diff(e.cov)}};
}

json FindingJson(const BlockFinding& f) {
  return {{"matrix", f.matrix},
          {"rows", f.rows},
          {"cols", f.cols},
          {"kind", f.kind},
          {"factor", f.factor},
          {"max_d", Number(f.max_d)},
          {"residual_d", Number(f.residual)}};
}

json BlockFindingsJson(const Explanation& e) {
  json out = json::array();
  for (const BlockAnalysis* a : {&e.J_bias_blocks, &e.cov_blocks})
    for (const auto& f : a->findings) out.push_back(FindingJson(f));
  return out;
}

json UnexplainedJson(const Explanation& e) {
  json out = json::array();
  for (const BlockAnalysis* a : {&e.J_bias_blocks, &e.cov_blocks})
    for (const auto& u : a->unexplained)
      out.push_back(
          {{"matrix", u.matrix}, {"rows", u.rows}, {"cols", u.cols}, {"max_d", Number(u.max_d)}});
  return out;
}

json EquivalentJson(const Equivalents& q) {
  json cov = json::array(), jac = json::array();
  for (const auto& c : q.cov) cov.push_back({{"convention", c.convention}, {"blocks", c.blocks}});
  for (const auto& j : q.J_bias)
    jac.push_back(
        {{"jacobian_convention", j.chart}, {"J_bias_columns", j.columns}, {"J_bias_sign", j.sign}});
  return {{"schemes", q.schemes}, {"cov", cov}, {"J_bias", jac}};
}

std::string ReportShort(double d) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1e", d);
  return b;
}

}  // namespace

json ReportJson(const CheckResult& r) {
  const Tolerances& tol = CheckTolerances();
  json out;
  out["verdict"] = Word(r.verdict);
  out["tolerances"] = {{"delta", tol.delta}, {"J_bias", tol.J_bias}, {"cov", tol.cov}};
  out["measurements"] = json::array();
  for (const auto& m : r.measurements) {
    json j;
    j["index"] = m.index;
    j["pointer"] = m.pointer;
    j["t_start"] = m.t_start;
    j["t_end"] = m.t_end;
    j["verdict"] = Word(m.judgement.verdict);
    j["declared"] = {{"convention", OrUnknown(m.declared.convention)},
                     {"blocks", OrUnknown(m.declared.blocks)},
                     {"jacobian_convention", OrUnknown(m.declared.jacobian_convention)},
                     {"jacobian_convention_implied", m.jacobian_convention_implied},
                     {"J_bias_columns", OrUnknown(m.declared.J_bias_columns)},
                     {"J_bias_sign", m.declared.J_bias_sign}};
    j["under_declaration"] = ExplanationJson(m.under_declaration);
    j["best"] = ExplanationJson(m.best);
    j["equivalent"] = EquivalentJson(m.best.equivalent);
    j["block_findings"] = BlockFindingsJson(m.best);
    j["unexplained_blocks"] = UnexplainedJson(m.best);
    j["sample_period"] = m.sample_period;
    j["precision"] = {{"numbers", m.float32 ? "float32" : "float64"},
                      {"inferred", m.float32_inferred}};
    j["dt_difference"] = m.dt_difference ? json(*m.dt_difference) : json(nullptr);
    j["dt_rounding_bound"] = m.dt_rounding_bound;
    j["findings"] = m.judgement.findings;
    if (!m.not_applicable.empty()) {
      json na = json::array();
      for (const auto& [scheme, reason] : m.not_applicable)
        na.push_back({{"scheme", scheme}, {"reason", reason}});
      j["not_applicable"] = std::move(na);
    }
    out["measurements"].push_back(std::move(j));
  }
  return out;
}

void PrintTable(std::ostream& out, const CheckResult& r) {
  const Tolerances& tol = CheckTolerances();
  out << "  #  interval [s]           verdict       scheme    covariance                          "
         "J_bias              "
         "max d: delta    J_bias   cov\n";
  for (const auto& m : r.measurements) {
    const Explanation& b = m.best;
    char head[64];
    std::snprintf(head, sizeof head, "%3zu  %9.3f .. %9.3f", m.index, m.t_start, m.t_end);
    std::string cov = b.convention + " " + BlockList(b.blocks);
    std::string jac = b.jacobian_convention +
                      (b.J_bias_columns.front() == "bg" ? " bg,ba" : " ba,bg") +
                      (b.J_bias_sign > 0 ? " +" : " -");
    char line[400];
    std::snprintf(line, sizeof line, "%s  %-12s  %-8s  %-34s  %-18s  %-8s  %-8s %-8s\n", head,
                  m.judgement.verdict == Verdict::consistent ? "consistent" : "INCONSISTENT",
                  b.scheme.c_str(), cov.c_str(), jac.c_str(), ReportShort(b.delta.max).c_str(),
                  ReportShort(b.J_bias.max).c_str(), ReportShort(b.cov.max).c_str());
    out << line;
    for (const auto& f : m.judgement.findings) out << "       - " << f << "\n";
    for (const auto& [scheme, reason] : m.not_applicable)
      out << "       - reference " << scheme << " not applicable: " << reason << "\n";
  }
  out << "verdict: " << Word(r.verdict) << " (tolerances on max d: delta " << tol.delta
      << ", J_bias " << tol.J_bias << ", cov " << tol.cov << "; docs/check.md)\n";
}

}  // namespace imuconv::check
