// The pieces several task kinds share, read and written (task_common.h).
#include "task_common.h"

#include <filesystem>

#include "imuconv/printable.h"
#include "input_checks.h"

namespace imuconv::pipeline {
namespace {

/// "ground_truth" as a state or bias: needs the top-level source. False (reported) otherwise.
bool GroundTruthString(const ParseContext& ctx, const Node& n, const std::string& expected) {
  if (n.value().get<std::string>() != "ground_truth") {
    n.fail("expected " + expected + " or \"ground_truth\", found the string " +
           QuotedShort(n.value().get<std::string>()));
    return false;
  }
  if (!ctx.has_gt) {
    n.fail("\"ground_truth\" needs a top-level /ground_truth source");
    return false;
  }
  return true;
}

/// A state or bias at `n`: its object form, read by read(spec), or "ground_truth".
template <typename Spec, typename Read>
std::optional<Spec> GroundTruthOr(const ParseContext& ctx, const Node& n,
                                  const std::string& expected, const Read& read) {
  Spec s;
  s.pointer = n.pointer();
  if (!n.value().is_string()) return read(s) ? std::optional<Spec>(s) : std::nullopt;
  if (!GroundTruthString(ctx, n, expected)) return std::nullopt;
  s.ground_truth = true;
  return s;
}

}  // namespace

std::string ParseContext::resolve(const std::string& p) const {
  namespace fs = std::filesystem;
  const fs::path path(p);
  if (path.is_absolute() || base_dir_.empty()) return path.lexically_normal().string();
  return (fs::path(base_dir_) / path).lexically_normal().string();
}

const std::string* ParseContext::earlier(const std::string& name) const {
  const auto it = earlier_.find(name);
  return it == earlier_.end() ? nullptr : &it->second;
}

void ParseContext::remember(const std::string& name, const std::string& type) {
  earlier_.emplace(name, type);
  if (type != "preintegrate") return;
  ++preintegrate_count_;
  if (preintegrate_names_.size() < 5) preintegrate_names_.push_back(name);
}

std::string ParseContext::earlier_preintegrate_names() const {
  std::string known;
  for (const auto& e : preintegrate_names_) known += (known.empty() ? "" : ", ") + Quoted(e);
  if (preintegrate_count_ > preintegrate_names_.size())
    known += " and " + std::to_string(preintegrate_count_ - preintegrate_names_.size()) + " more";
  return known;
}

std::optional<StateSpec> ReadStateSpec(const ParseContext& ctx, const Node& n) {
  return GroundTruthOr<StateSpec>(ctx, n, "a state object {p, q_wxyz, v, bg, ba}",
                                  [&](StateSpec& s) {
                                    const auto x = StateFromJson(n);
                                    if (x) s.x = *x;
                                    return x.has_value();
                                  });
}

std::optional<BiasSpec> ReadBiasSpec(const ParseContext& ctx, const Node& n) {
  return GroundTruthOr<BiasSpec>(ctx, n, "{\"bg\": [3], \"ba\": [3]}", [&](BiasSpec& b) {
    if (!n.expect_object({"bg", "ba"})) return false;
    const auto bg = n.vec3("bg", true);
    const auto ba = n.vec3("ba", true);
    if (!bg || !ba) return false;
    b.bg = *bg;
    b.ba = *ba;
    return true;
  });
}

std::optional<CovSpec> ReadCovSpec(const Node& n) {
  CovSpec cs;
  auto m = Matrix15FromJson(n);
  if (!m || !CheckCovarianceInput(n.checker(), n.pointer(), m->m)) return std::nullopt;
  cs.given = true;
  cs.in = std::make_shared<const Matrix15In>(std::move(*m));
  return cs;
}

void ReadStart(const ParseContext& ctx, const Node& task, StateSpec& state, CovSpec& cov) {
  const auto sn = task.get("start", true);
  if (!sn || !sn->expect_object({"state", "cov"})) return;
  if (auto st = sn->get("state", true))
    if (auto s = ReadStateSpec(ctx, *st)) state = *s;
  if (auto cn = sn->get("cov", false))
    if (auto cv = ReadCovSpec(*cn)) cov = *cv;
}

std::optional<MeasurementsSpec> ReadMeasurementsSpec(const ParseContext& ctx, const Node& task) {
  const auto n = task.get("measurements", true);
  if (!n) return std::nullopt;
  MeasurementsSpec m;
  m.pointer = n->pointer();
  if (n->value().is_string()) {
    const std::string name = n->value().get<std::string>();
    const std::string* type = ctx.earlier(name);
    if (!type) {
      const std::string known = ctx.earlier_preintegrate_names();
      n->fail("no earlier preintegrate task named " + Quoted(name) +
              (known.empty() ? std::string(" (there is none before this task)")
                             : " (earlier ones: " + known + ")"));
      return std::nullopt;
    }
    if (*type != "preintegrate") {
      n->fail("task " + Quoted(name) + " is a " + *type +
              " task; measurements come from a preintegrate task");
      return std::nullopt;
    }
    m.task = name;
    return m;
  }
  if (n->is_object()) {
    if (!n->expect_object({"file"})) return std::nullopt;
    if (auto f = n->string("file", true)) {
      m.file = ctx.resolve(*f);
      return m;
    }
    return std::nullopt;
  }
  n->fail("expected the name of an earlier preintegrate task or {\"file\": PATH}, found " +
          TypeName(n->value()));
  return std::nullopt;
}

std::optional<std::string> ReadPluginId(const Node& task, const char* key, bool required,
                                        std::string* pointer) {
  if (pointer) *pointer = task.child_pointer(key);
  auto s = task.string(key, required);
  if (s && s->empty()) {
    task.checker().error(task.child_pointer(key), "expected a plugin id, found an empty string");
    return std::nullopt;
  }
  return s;
}

std::optional<std::size_t> ReadIndex(const Node& task) {
  if (auto in = task.get("index", false)) {
    if (auto i = in->integer()) {
      if (*i < 0) {
        in->fail("expected an index >= 0");
        return std::nullopt;
      }
      return static_cast<std::size_t>(*i);
    }
  }
  return std::nullopt;
}

std::optional<bool> ReadCompareGroundTruth(const ParseContext& ctx, const Node& task) {
  const auto b = task.boolean("compare_ground_truth", false);
  if (b && *b && !ctx.has_gt)
    task.checker().error(task.child_pointer("compare_ground_truth"),
                         "needs a top-level /ground_truth source");
  return b;
}

void RequireImu(const ParseContext& ctx, const Node& task, const std::string& type) {
  if (!ctx.has_imu)
    task.checker().error(task.child_pointer("type"),
                         "a " + type + " task needs IMU samples: add a top-level /imu source");
}

void WriteTimes(JsonWriter& w, std::optional<double> ts, std::optional<double> te,
                const std::optional<TimeOrigin>& origin) {
  if (ts) {
    w.key("t_start");
    w.number(*ts);
  }
  if (te) {
    w.key("t_end");
    w.number(*te);
  }
  if (!origin) return;
  if (ts)
    if (auto a = origin->absolute_ns(*ts)) {
      w.key("t_start_abs_ns");
      w.integer(*a);
    }
  if (te)
    if (auto a = origin->absolute_ns(*te)) {
      w.key("t_end_abs_ns");
      w.integer(*a);
    }
}

void WriteMeasurementsSource(JsonWriter& w, const MeasurementsSpec& m) {
  w.key("measurements");
  if (m.task.empty()) {
    w.begin_object();
    w.key("file");
    w.string(m.file);
    w.end_object();
  } else {
    w.string(m.task);
  }
}

std::string MeasurementsName(const MeasurementsSpec& m) {
  return m.task.empty() ? "file " + Printable(m.file) : "task " + Quoted(m.task);
}

}  // namespace imuconv::pipeline
