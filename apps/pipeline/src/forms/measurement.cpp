// The measurement form, read (measurements files) and written (measurement.h).
#include "imuconv/pipeline/measurement.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "../io/message_text.h"
#include "chart_matrix.h"
#include "imuconv/pipeline/block_labels.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/printable.h"
#include "increment.h"
#include "input_checks.h"
#include "state.h"
#include "task_common.h"

namespace imuconv::pipeline {
namespace {

// Two statements of one time (t_start and t_start_abs_ns, or dt and t_end - t_start) agree
// within this: far above the 1 ns of the stamps and the round-off of relative seconds, far
// below any IMU sample period.
constexpr double kTimeAgreement = 1e-6;
void ReadJBias(const Node& n, const Registry& reg, const std::string& cov_conv, Preintegrated& in) {
  if (!n.expect_object({"convention", "rows", "cols", "matrix"})) return;
  std::string chart;
  std::optional<std::vector<std::string>> rows, cols;
  if (auto cv = n.string("convention", false)) chart = *cv;
  for (auto [key, dst] :
       {std::pair<const char*, std::optional<std::vector<std::string>>*>{"rows", &rows},
        {"cols", &cols}}) {
    if (auto rn = n.get(key, false)) {
      if (!rn->expect_object({"convention", "blocks"})) continue;
      if (auto cv = rn->string("convention", false)) {
        if (!chart.empty() && chart != *cv)
          rn->checker().error(rn->child_pointer("convention"),
                              Quoted(*cv) + " differs from the J_bias chart " + Quoted(chart));
        chart = *cv;
      }
      if (auto bn = rn->get("blocks", false))
        if (auto b = bn->string_list()) *dst = *b;
    }
  }
  if (!chart.empty()) {
    CheckPluginId(n.checker(), reg, PluginKind::IncrementConvention, chart,
                  n.child_pointer("convention"));
    if (!reg.has(PluginKind::IncrementConvention, chart)) return;
  } else if (!cov_conv.empty()) {
    chart = reg.info(PluginKind::IncrementConvention, cov_conv).jacobian_convention;
    if (chart.empty()) chart = cov_conv;
  }
  if (!chart.empty()) {
    const auto labels = Blocks(reg, PluginKind::IncrementConvention, chart);
    if (rows && *rows != NavLabels(labels))
      n.checker().error(n.child_pointer("rows") + "/blocks",
                        "rows [" + Printable(Join(*rows)) + "] do not match the order of '" +
                            chart + "': [" + Join(NavLabels(labels)) + "]");
    if (cols && *cols != BiasLabels(labels))
      n.checker().error(n.child_pointer("cols") + "/blocks",
                        "cols [" + Printable(Join(*cols)) + "] do not match the bias order of '" +
                            chart + "': [" + Join(BiasLabels(labels)) + "]");
  }
  in.jacobian_convention = chart;
  if (auto mn = n.get("matrix", true))
    if (auto m = mn->matrix(9, 6)) in.J_bias = *m;
}

/// t_start / t_end of one measurement on the pipeline's time axis. Absolute stamps place it
/// when the pipeline has an origin; a relative time is shifted by the file's own origin. When
/// both are given and comparable they must agree (neither silently wins).
void ReadTimes(const Node& e, std::optional<std::int64_t> file_origin,
               std::optional<std::int64_t> origin_ns, MeasRecord& r) {
  for (auto [key, abs_key, dst] : {std::tuple<const char*, const char*, std::optional<double>*>{
                                       "t_start", "t_start_abs_ns", &r.t_s},
                                   {"t_end", "t_end_abs_ns", &r.t_e}}) {
    std::optional<double> from_abs, from_rel;
    if (auto a = e.integer(abs_key, false); a && origin_ns)
      from_abs = static_cast<double>(*a - *origin_ns) * 1e-9;
    if (auto t = e.number(key, false)) {
      from_rel = *t;
      if (file_origin && origin_ns)
        *from_rel = *t + static_cast<double>(*file_origin - *origin_ns) * 1e-9;
    }
    if (from_abs && from_rel && std::abs(*from_abs - *from_rel) > kTimeAgreement)
      e.checker().error(
          e.child_pointer(key),
          std::string(key) + " places the measurement at " + Num(*from_rel, 15) + " s but " +
              abs_key + " at " + Num(*from_abs, 15) +
              " s on the IMU data's time axis (tolerance 1e-6 s); give one, or make them agree");
    *dst = from_abs ? from_abs : from_rel;
  }
}

}  // namespace

namespace {

const std::vector<std::string> kMeasurementKeys = {
    "index", "t_start", "t_end", "t_start_abs_ns", "t_end_abs_ns", "dt", "n_knots", "bias_estimate",
    "delta", "J_bias",  "cov",   "expressed",      "precision"};

/// True when every number under `j` is a float32 value, and there is at least one number.
bool AllFloat32(const json& j, std::size_t& count) {
  if (j.is_number()) {
    ++count;
    const double v = j.get<double>();
    return std::isfinite(v) && static_cast<double>(static_cast<float>(v)) == v;
  }
  if (j.is_array() || j.is_object()) {
    for (const auto& x : j)
      if (!AllFloat32(x, count)) return false;
  }
  return true;
}

/// NumberPrecision of measurement `e` (measurement.h).
NumberPrecision ReadPrecision(const Node& e) {
  NumberPrecision p;
  if (auto s = e.string("precision", false)) {
    p.inferred = false;
    if (*s == "float32")
      p.float32 = true;
    else if (*s != "float64")
      e.checker().error(e.child_pointer("precision"),
                        "expected \"float64\" or \"float32\" (the precision the numbers "
                        "were computed in)");
    return p;
  }
  const json& v = e.value();
  std::size_t count = 0;
  bool all = true;
  for (const char* key : {"delta", "J_bias", "cov"})
    if (v.contains(key)) {
      const json& part = v.at(key);
      const bool matrix =
          key != std::string("delta") && part.is_object() && part.contains("matrix");
      all = all && AllFloat32(matrix ? part.at("matrix") : part, count);
    }
  p.float32 = all && count > 0;
  return p;
}

double CovarianceTolerance(const NumberPrecision& p) {
  return p.float32 ? kCovarianceTolFloat32 : kCovarianceTol;
}

/// The envelope every measurements file shares: the root object, its optional origin and the
/// non-empty "measurements" array (nullopt after reporting what is wrong).
std::optional<Node> MeasurementArray(const Node& root, std::optional<std::int64_t>& file_origin) {
  if (!root.expect_object({"$schema", "description", "time_origin_ns", "measurements"}))
    return std::nullopt;
  if (auto o = root.integer("time_origin_ns", false)) file_origin = *o;
  const auto ms = root.get("measurements", true);
  if (ms && (!ms->is_array() || ms->size() == 0))
    ms->fail("expected a non-empty array of measurements");
  if (!ms || !ms->is_array()) return std::nullopt;
  return ms;
}

/// Reads a measurements document: the envelope (MeasurementArray), then `read(c, e, i,
/// file_origin)` for each element e (at position i) that is an object of the known keys,
/// keeping what it returns (nullopt: nothing, its errors reported on c); then throws every
/// error found, each with `file` and its JSON pointer.
template <typename T, typename ReadOne>
std::vector<T> ReadEachMeasurement(const json& doc, const std::string& file, ReadOne read) {
  Checker c(file);
  const Node root(doc, "", c);
  std::vector<T> out;
  std::optional<std::int64_t> file_origin;
  const auto ms = MeasurementArray(root, file_origin);
  if (!ms) c.throw_if_errors();
  for (std::size_t i = 0; i < ms->size(); ++i) {
    const Node e = (*ms)[i];
    if (!e.expect_object(kMeasurementKeys)) continue;
    if (std::optional<T> v = read(c, e, i, file_origin)) out.push_back(std::move(*v));
  }
  c.throw_if_errors();
  return out;
}

/// The fields whose meaning does not depend on a chart: times, index, dt, bias estimate and
/// increment.
void ReadChartFreeFields(const Node& e, std::size_t i, std::optional<std::int64_t> file_origin,
                         std::optional<std::int64_t> origin_ns, MeasRecord& r, Preintegrated& in) {
  ReadTimes(e, file_origin, origin_ns, r);
  // Tasks refer to a measurement by its position ("index" of residual and bias_update
  // tasks): an "index" that says otherwise would be silently wrong.
  if (auto in = e.get("index", false))
    if (auto k = in->integer(); k && *k != static_cast<std::int64_t>(i))
      in->fail("index " + std::to_string(*k) + " is not the measurement's position " +
               std::to_string(i) + " in the array (tasks refer to measurements by position)");
  if (auto dt = e.number("dt", true)) {
    if (!(*dt > 0.0))
      e.checker().error(e.child_pointer("dt"), "expected a positive duration");
    else
      in.dt = *dt;
  }
  if (auto bn = e.get("bias_estimate", true)) {
    if (bn->expect_object({"bg", "ba"})) {
      if (auto v = bn->vec3("bg", true)) in.bg_hat = *v;
      if (auto v = bn->vec3("ba", true)) in.ba_hat = *v;
    }
  }
  if (auto dn = e.get("delta", true))
    if (auto d = IncrementFromJson(*dn)) in.delta = *d;
}

void CheckDtAgainstTimes(const Node& e, const MeasRecord& r, double dt) {
  if (r.t_s && r.t_e && std::abs((*r.t_e - *r.t_s) - dt) > kTimeAgreement)
    e.checker().error(e.child_pointer("dt"),
                      "dt = " + Num(dt, 10) + " s does not match t_end - t_start = " +
                          Num(*r.t_e - *r.t_s, 10) + " s (tolerance 1e-6 s)");
}

// ---- the declared form (imuconv check): any chart may be missing or "unknown" ----

constexpr const char* kUnknown = "unknown";

/// A convention id as declared: "" when missing or "unknown", else a registered increment
/// convention (an unknown id is reported: a typo is not "unknown").
std::string DeclaredConvention(const Node& n, const char* key, const Registry& reg) {
  const auto cv = n.string(key, false);
  if (!cv || *cv == kUnknown) return "";
  CheckPluginId(n.checker(), reg, PluginKind::IncrementConvention, *cv, n.child_pointer(key));
  return reg.has(PluginKind::IncrementConvention, *cv) ? *cv : "";
}

/// A declared block order: {} when missing or "unknown" (then `unknown` is set), else an
/// ordering of `labels` (each once; reported otherwise).
std::vector<std::string> DeclaredBlocks(const Node& parent, const char* key,
                                        std::vector<std::string> labels, bool* unknown = nullptr) {
  const auto bn = parent.get(key, false);
  if (!bn) return {};
  if (bn->is_string() && bn->value().get<std::string>() == kUnknown) {
    if (unknown) *unknown = true;
    return {};
  }
  const auto b = bn->string_list();
  if (!b) return {};
  std::vector<std::string> sorted = *b;
  std::sort(sorted.begin(), sorted.end());
  std::sort(labels.begin(), labels.end());
  if (sorted != labels) {
    bn->fail("blocks [" + Printable(Join(*b)) + "] are not an ordering of [" + Join(labels) +
             "] (or \"unknown\")");
    return {};
  }
  return *b;
}

void ReadDeclaredCov(const Node& cn, const Registry& reg, DeclaredMeasurement& out) {
  if (!cn.expect_object({"convention", "blocks", "matrix"})) return;
  out.in.convention = DeclaredConvention(cn, "convention", reg);
  out.cov_blocks =
      DeclaredBlocks(cn, "blocks", {"theta", "p", "v", "bg", "ba"}, &out.cov_blocks_unknown);
  if (auto mn = cn.get("matrix", true))
    if (auto m = mn->matrix(15, 15)) {
      out.in.cov = *m;
      CheckCovarianceInput(cn.checker(), mn->pointer(), out.in.cov,
                           CovarianceTolerance(out.precision));
    }
}

void ReadDeclaredJBias(const Node& n, const Registry& reg, DeclaredMeasurement& out) {
  if (!n.expect_object({"convention", "rows", "cols", "matrix"})) return;
  std::string chart = DeclaredConvention(n, "convention", reg);
  bool chart_written = n.has("convention");  // an id or "unknown"
  for (const char* key : {"rows", "cols"}) {
    const auto rn = n.get(key, false);
    if (!rn || !rn->expect_object({"convention", "blocks"})) continue;
    chart_written = chart_written || rn->has("convention");
    const std::string cv = DeclaredConvention(*rn, "convention", reg);
    if (!cv.empty() && !chart.empty() && cv != chart)
      rn->checker().error(rn->child_pointer("convention"),
                          Quoted(cv) + " differs from the J_bias chart " + Quoted(chart));
    if (!cv.empty()) chart = cv;
    if (std::string(key) == "rows")
      out.J_bias_rows = DeclaredBlocks(*rn, "blocks", {"theta", "p", "v"});
    else
      out.J_bias_cols = DeclaredBlocks(*rn, "blocks", {"bg", "ba"}, &out.J_bias_cols_unknown);
  }
  // As ReadMeasurementFile: with no chart of its own, J_bias is in the chart the covariance's
  // convention names for its bias Jacobian.
  if (!chart_written && !out.in.convention.empty()) {
    chart = reg.info(PluginKind::IncrementConvention, out.in.convention).jacobian_convention;
    if (chart.empty()) chart = out.in.convention;
    out.jacobian_convention_implied = true;
  }
  if (!chart.empty() && !out.J_bias_rows.empty()) {
    const auto labels = NavLabels(Blocks(reg, PluginKind::IncrementConvention, chart));
    if (out.J_bias_rows != labels)
      n.checker().error(n.child_pointer("rows") + "/blocks",
                        "rows [" + Join(out.J_bias_rows) + "] do not match the order of '" + chart +
                            "': [" + Join(labels) + "]");
  }
  out.in.jacobian_convention = chart;
  if (auto mn = n.get("matrix", true))
    if (auto m = mn->matrix(9, 6)) out.in.J_bias = *m;
}

}  // namespace

std::vector<MeasRecord> ReadMeasurementDocument(const json& doc, const std::string& file,
                                                const Registry& reg,
                                                std::optional<std::int64_t> origin_ns) {
  return ReadEachMeasurement<MeasRecord>(
      doc, file,
      [&](Checker& c, const Node& e, std::size_t i,
          std::optional<std::int64_t> file_origin) -> std::optional<MeasRecord> {
        const std::size_t before = c.count();
        MeasRecord r;
        r.pointer = e.pointer();
        Preintegrated in;
        ReadChartFreeFields(e, i, file_origin, origin_ns, r, in);
        const NumberPrecision precision = ReadPrecision(e);
        std::string cov_conv;
        if (auto cn = e.get("cov", true)) {
          if (cn->expect_object({"convention", "blocks", "matrix"})) {
            if (auto cv = cn->string("convention", true)) {
              CheckPluginId(c, reg, PluginKind::IncrementConvention, *cv,
                            cn->child_pointer("convention"));
              if (reg.has(PluginKind::IncrementConvention, *cv)) cov_conv = *cv;
            }
            if (auto mn = cn->get("matrix", true))
              if (auto m = mn->matrix(15, 15)) {
                in.cov = *m;
                CheckCovarianceInput(c, mn->pointer(), in.cov, CovarianceTolerance(precision));
              }
            if (auto bn = cn->get("blocks", false))
              if (auto b = bn->string_list(); b && !cov_conv.empty()) {
                const auto expect = Blocks(reg, PluginKind::IncrementConvention, cov_conv);
                if (*b != expect)
                  bn->fail("blocks [" + Printable(Join(*b)) +
                           "] do not match the block order of '" + cov_conv + "': [" +
                           Join(expect) + "]");
              }
          }
        }
        in.convention = cov_conv;
        if (auto jn = e.get("J_bias", true)) ReadJBias(*jn, reg, cov_conv, in);
        if (c.count() != before) return std::nullopt;
        r.convention = in.convention;
        r.jacobian_convention = in.jacobian_convention;
        try {
          r.m = FromConvention(reg, in);
        } catch (const std::exception& ex) {
          e.fail(std::string("cannot bring the measurement into the reference chart: ") +
                 ex.what());
          return std::nullopt;
        }
        CheckDtAgainstTimes(e, r, in.dt);
        return r;
      });
}

std::optional<double> DtDifference(const DeclaredMeasurement& m) {
  if (!m.t_s || !m.t_e) return std::nullopt;
  const double d = m.in.dt - (*m.t_e - *m.t_s);
  if (std::abs(d) <= kTimeAgreement) return std::nullopt;
  return d;
}

std::vector<DeclaredMeasurement> ReadDeclaredMeasurementFile(
    const std::string& path, const Registry& reg, std::optional<std::int64_t> origin_ns) {
  return ReadDeclaredMeasurementDocument(ParseJsonFile(path), path, reg, origin_ns);
}

std::vector<DeclaredMeasurement> ReadDeclaredMeasurementDocument(
    const json& doc, const std::string& path, const Registry& reg,
    std::optional<std::int64_t> origin_ns) {
  return ReadEachMeasurement<DeclaredMeasurement>(
      doc, path,
      [&](Checker& c, const Node& e, std::size_t i,
          std::optional<std::int64_t> file_origin) -> std::optional<DeclaredMeasurement> {
        const std::size_t before = c.count();
        MeasRecord r;
        DeclaredMeasurement d;
        d.pointer = e.pointer();
        // No pipeline origin: times stay on the file's own axis, in seconds as written (the file's
        // own time_origin_ns then shifts nothing, as in ReadMeasurementFile without an origin).
        ReadChartFreeFields(e, i, origin_ns ? file_origin : std::nullopt, origin_ns, r, d.in);
        d.precision = ReadPrecision(e);
        if (auto cn = e.get("cov", true)) ReadDeclaredCov(*cn, reg, d);
        if (auto jn = e.get("J_bias", true)) ReadDeclaredJBias(*jn, reg, d);
        // dt is not compared with t_end - t_start here: a dt that differs is what check reports
        // (DtDifference), not a reason to refuse the numbers (a float32 sum of the steps differs).
        if (c.count() != before) return std::nullopt;
        d.t_s = r.t_s;
        d.t_e = r.t_e;
        return d;
      });
}

std::vector<MeasRecord> ReadMeasurementFile(const std::string& path, const Registry& reg,
                                            std::optional<std::int64_t> origin_ns) {
  return ReadMeasurementDocument(ParseJsonFile(path), path, reg, origin_ns);
}

void WriteMeasurement(JsonWriter& w, const MeasRecord& r, std::size_t k,
                      const std::vector<std::string>& conventions, const Registry& reg,
                      const OmitSpec& omit, const std::optional<TimeOrigin>& origin) {
  static const std::string kRef = "preint_reference";
  const Preintegrated& m = r.m;
  w.begin_object();
  w.key("index");
  w.unsigned_integer(k);
  WriteTimes(w, r.t_s, r.t_e, origin);
  w.key("dt");
  w.number(m.dt);
  if (r.n_knots) {
    w.key("n_knots");
    w.unsigned_integer(r.n_knots);
  }
  w.key("bias_estimate");
  WriteBias(w, m.bg_hat, m.ba_hat);
  w.key("delta");
  WriteIncrement(w, m.delta, !omit.R);
  const bool reference = conventions.empty() || !omit.reference;
  const auto& ref_blocks = reg.info(PluginKind::IncrementConvention, kRef).blocks;
  if (reference && !omit.J_bias) {
    w.key("J_bias");
    WriteMixed(w, m.J_bias, kRef, NavLabels(ref_blocks), kRef, BiasLabels(ref_blocks));
  }
  if (reference && !omit.cov) {
    w.key("cov");
    WriteCovariance(w, m.cov, kRef, ref_blocks);
  }
  if (!conventions.empty() && !(omit.J_bias && omit.cov)) {
    w.key("expressed");
    w.begin_object();
    for (const auto& c : conventions) {
      const Preintegrated in = Express(reg, m, c);
      const auto& jb = reg.info(PluginKind::IncrementConvention, in.jacobian_convention).blocks;
      w.key(c);
      w.begin_object();
      if (!omit.J_bias) {
        w.key("J_bias");
        WriteMixed(w, in.J_bias, in.jacobian_convention, NavLabels(jb), in.jacobian_convention,
                   BiasLabels(jb));
      }
      if (!omit.cov) {
        w.key("cov");
        WriteCovariance(w, in.cov, in.convention,
                        reg.info(PluginKind::IncrementConvention, in.convention).blocks);
      }
      w.end_object();
    }
    w.end_object();
  }
  w.end_object();
}

}  // namespace imuconv::pipeline
