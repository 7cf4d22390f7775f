// Structural validation of pipeline documents (no registry, no data yet).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unordered_map>
#include <unordered_set>

#include "imuconv/pipeline/pipeline.h"
#include "imuconv/printable.h"
#include "imuconv/so3.h"
#include "input_checks.h"
#include "intervals.h"
#include "spec.h"

namespace imuconv::pipeline {
namespace {

namespace fs = std::filesystem;

std::string Resolve(const std::string& base_dir, const std::string& p) {
  const fs::path path(p);
  if (path.is_absolute() || base_dir.empty()) return path.lexically_normal().string();
  return (fs::path(base_dir) / path).lexically_normal().string();
}

bool ValidName(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
  });
}

/// A time: a JSON number, or a string with a plain decimal (exact for huge values).
std::optional<TimeValue> TimeFromJson(const Node& n) {
  if (n.value().is_number_integer()) {
    if (auto i = n.integer()) return TimeValue{*i, 0.0};
    return std::nullopt;
  }
  if (n.value().is_number_float()) {
    if (auto d = n.number()) return TimeValueFromDouble(*d);
    return std::nullopt;
  }
  if (n.value().is_string()) {
    if (auto t = ParseTimeValue(n.value().get<std::string>())) return t;
    n.fail("expected a decimal time, found '" + n.value().get<std::string>() + "'");
    return std::nullopt;
  }
  n.fail("expected a time (a number, or a string holding a decimal number), found " + TypeName(n.value()));
  return std::nullopt;
}

struct Parser {
  Checker& c;
  const std::string& base_dir;
  bool has_gt = false;
  bool has_imu = false;
  // name -> type of the earlier tasks: looked up once per reference, so that validation
  // stays linear in the number of tasks.
  std::unordered_map<std::string, std::string> earlier;
  // The first few earlier preintegrate task names, in order, for messages.
  std::vector<std::string> preintegrate_names;
  std::size_t preintegrate_count = 0;

  // ---- IMU source ---------------------------------------------------------------------
  std::optional<ImuSourceSpec> Imu(const Node& n) {
    if (!n.is_object()) {
      n.fail("expected an object with \"format\": \"euroc\", \"csv\" or \"inline\", found " + TypeName(n.value()));
      return std::nullopt;
    }
    ImuSourceSpec s;
    s.pointer = n.pointer();
    const auto fmt = n.get("format", true);
    std::optional<std::string> f;
    if (fmt) f = fmt->one_of({"euroc", "csv", "inline"});
    if (!f) {
      n.expect_object({"format", "path", "time_origin_ns", "delimiter", "header_rows", "comment", "time_unit", "columns",
                       "time_origin", "samples", "max_gap_factor", "allow_gaps"});
      return std::nullopt;
    }
    if (*f == "euroc") {
      s.format = ImuSourceSpec::Format::Euroc;
      n.expect_object({"format", "path", "time_origin_ns", "max_gap_factor", "allow_gaps"});
      if (auto p = n.string("path", true)) s.path = Resolve(base_dir, *p);
      if (auto o = n.get("time_origin_ns", false)) {
        if (o->value().is_string()) {
          auto t = TimeFromJson(*o);
          if (t && t->frac != 0.0)
            o->fail("expected an integer number of nanoseconds");
          else if (t)
            s.origin_ns = t->whole;
        } else if (auto i = o->integer()) {
          s.origin_ns = *i;
        }
      }
    } else if (*f == "csv") {
      s.format = ImuSourceSpec::Format::Csv;
      n.expect_object({"format", "path", "delimiter", "header_rows", "comment", "time_unit", "columns", "time_origin",
                       "max_gap_factor", "allow_gaps"});
      if (auto p = n.string("path", true)) s.path = Resolve(base_dir, *p);
      if (auto dn = n.get("delimiter", false)) {
        if (auto d = dn->string()) {
          if (*d == "whitespace")
            s.csv.whitespace_delimited = true;
          else if (d->size() == 1 && (*d)[0] != '"' && (*d)[0] != '\n')
            s.csv.delimiter = (*d)[0];
          else
            dn->fail("expected one character (e.g. \",\", \";\", \"\\t\") or \"whitespace\", found '" + *d + "'");
        }
      }
      if (auto hn = n.get("header_rows", false)) {
        if (auto h = hn->integer()) {
          if (*h < 0 || *h > 1000)
            hn->fail("expected an integer from 0 to 1000");
          else
            s.csv.header_rows = static_cast<int>(*h);
        }
      }
      if (auto cm = n.string("comment", false)) s.csv.comment = *cm;
      if (auto un = n.get("time_unit", false))
        if (auto u = un->one_of({"s", "ms", "us", "ns"})) s.csv.time_unit = *ParseTimeUnit(*u);
      if (auto cn = n.get("columns", true)) {
        std::vector<std::string> names(kImuColumnNames.begin(), kImuColumnNames.end());
        if (cn->expect_object(names)) {
          for (std::size_t k = 0; k < 7; ++k) {
            auto col = cn->get(kImuColumnNames[k], true);
            if (!col) continue;
            if (col->value().is_string()) {
              s.csv.columns[k] = col->value().get<std::string>();
            } else if (col->value().is_number_integer()) {
              const auto i = col->integer();
              if (i && *i >= 0 && *i < 100000)
                s.csv.columns[k] = static_cast<int>(*i);
              else
                col->fail("expected a column index >= 0");
            } else {
              col->fail("expected a 0-based column index or a header name, found " + TypeName(col->value()));
            }
          }
        }
      }
      if (auto o = n.get("time_origin", false))
        if (auto t = TimeFromJson(*o)) s.csv.time_origin = *t;
    } else {
      s.format = ImuSourceSpec::Format::Inline;
      s.path = "inline";
      n.expect_object({"format", "samples", "time_unit", "time_origin", "max_gap_factor", "allow_gaps"});
      if (auto un = n.get("time_unit", false))
        if (auto u = un->one_of({"s", "ms", "us", "ns"})) s.csv.time_unit = *ParseTimeUnit(*u);
      if (auto o = n.get("time_origin", false))
        if (auto t = TimeFromJson(*o)) s.csv.time_origin = *t;
      if (auto sn = n.get("samples", true)) {
        if (!sn->is_array() || sn->size() < 2) {
          sn->fail("expected an array of at least 2 samples [t, wx, wy, wz, ax, ay, az]");
        } else {
          for (std::size_t i = 0; i < sn->size(); ++i) {
            const Node row = (*sn)[i];
            if (!row.is_array() || row.size() != 7) {
              row.fail("expected a sample [t, wx, wy, wz, ax, ay, az] (7 numbers), found " +
                       (row.is_array() ? "an array of " + std::to_string(row.size()) : TypeName(row.value())));
              continue;
            }
            const auto t = TimeFromJson(row[0]);
            ImuSample smp;
            bool ok = t.has_value();
            for (std::size_t k = 1; k < 7; ++k) {
              const auto v = row[k].number();
              if (!v) {
                ok = false;
                continue;
              }
              if (k <= 3)
                smp.gyro[static_cast<Eigen::Index>(k - 1)] = *v;
              else
                smp.accel[static_cast<Eigen::Index>(k - 4)] = *v;
            }
            if (!ok) continue;
            if (!s.inline_t.empty()) {
              const TimeValue& prev = s.inline_t.back();
              if (!(t->whole > prev.whole || (t->whole == prev.whole && t->frac > prev.frac))) {
                row[0].fail("time is not after the previous sample's; sample times must be strictly increasing");
                continue;
              }
            }
            s.inline_t.push_back(*t);
            s.inline_raw.push_back(smp);
            s.inline_index.push_back(i);
          }
        }
      }
    }
    s.timing = Timing(n);
    if (s.format == ImuSourceSpec::Format::Inline) CheckInlineTiming(n, s);
    return s;
  }

  /// "max_gap_factor" (> 1, default 10) and "allow_gaps" (default false) of an IMU or
  /// ground-truth source.
  static TimingPolicy Timing(const Node& n) {
    TimingPolicy t;
    if (auto fn = n.get("max_gap_factor", false))
      if (auto f = fn->number()) {
        if (!(*f > 1.0))
          fn->fail("expected a number > 1 (a gap longer than this many median sample periods is an error)");
        else
          t.max_gap_factor = *f;
      }
    if (auto b = n.boolean("allow_gaps", false)) t.allow_gaps = *b;
    return t;
  }

  /// Inline samples get the readers' timing checks (rate, gaps), reported at the sample.
  static void CheckInlineTiming(const Node& n, const ImuSourceSpec& s) {
    if (s.inline_t.size() < 2 || s.inline_t.size() != s.inline_index.size()) return;
    TimeOrigin o;
    o.unit = s.csv.time_unit;
    if (s.csv.time_origin) o.value = *s.csv.time_origin;
    std::vector<double> t;
    t.reserve(s.inline_t.size());
    for (const auto& v : s.inline_t) t.push_back(o.relative_seconds(v));
    const auto issue = FindTimingIssue(t, s.timing, s.csv.time_unit, TimeSource::imu);
    if (!issue) return;
    if (issue->kind == TimingIssue::Kind::gap && issue->index < s.inline_index.size())
      n.checker().error(n.child_pointer("samples") + "/" + std::to_string(s.inline_index[issue->index]) + "/0",
                        issue->message);
    else
      n.checker().error(n.child_pointer(n.has("time_unit") ? "time_unit" : "samples"), issue->message);
  }

  // ---- task pieces --------------------------------------------------------------------
  std::optional<StateSpec> State(const Node& n) {
    StateSpec s;
    s.pointer = n.pointer();
    if (n.value().is_string()) {
      if (n.value().get<std::string>() != "ground_truth") {
        n.fail("expected a state object {p, q_wxyz, v, bg, ba} or \"ground_truth\", found the string '" +
               n.value().get<std::string>() + "'");
        return std::nullopt;
      }
      if (!has_gt) {
        n.fail("\"ground_truth\" needs a top-level /ground_truth source");
        return std::nullopt;
      }
      s.ground_truth = true;
      return s;
    }
    auto x = StateFromJson(n);
    if (!x) return std::nullopt;
    s.x = *x;
    return s;
  }

  std::optional<BiasSpec> Bias(const Node& n) {
    BiasSpec b;
    b.pointer = n.pointer();
    if (n.value().is_string()) {
      if (n.value().get<std::string>() != "ground_truth") {
        n.fail("expected {\"bg\": [3], \"ba\": [3]} or \"ground_truth\", found the string '" + n.value().get<std::string>() + "'");
        return std::nullopt;
      }
      if (!has_gt) {
        n.fail("\"ground_truth\" needs a top-level /ground_truth source");
        return std::nullopt;
      }
      b.ground_truth = true;
      return b;
    }
    if (!n.expect_object({"bg", "ba"})) return std::nullopt;
    const auto bg = n.vec3("bg", true);
    const auto ba = n.vec3("ba", true);
    if (!bg || !ba) return std::nullopt;
    b.bg = *bg;
    b.ba = *ba;
    return b;
  }

  /// A start covariance: read, and refused (never repaired) unless it is one.
  std::optional<CovSpec> Cov(const Node& n) {
    CovSpec cs;
    auto m = Matrix15FromJson(n);
    if (!m || !CheckCovarianceInput(n.checker(), n.pointer(), m->m)) return std::nullopt;
    cs.given = true;
    cs.in = std::make_shared<const Matrix15In>(std::move(*m));
    return cs;
  }

  /// "start": {"state": ..., "cov": ...}.
  void Start(const Node& task, StateSpec& state, CovSpec& cov) {
    const auto sn = task.get("start", true);
    if (!sn || !sn->expect_object({"state", "cov"})) return;
    if (auto st = sn->get("state", true))
      if (auto s = State(*st)) state = *s;
    if (auto cn = sn->get("cov", false))
      if (auto cv = Cov(*cn)) cov = *cv;
  }

  /// "interval": {"t_start", "t_end"} and/or "keyframes": [...] | {"start","end","step"}.
  std::optional<IntervalsSpec> Intervals(const Node& task, bool allow_keyframes) {
    const bool has_i = task.has("interval"), has_k = task.has("keyframes");
    if (!allow_keyframes && has_k) return std::nullopt;  // reported as an unknown key
    if (has_i && has_k) {
      task.checker().error(task.child_pointer("keyframes"), "give either \"interval\" or \"keyframes\", not both");
      return std::nullopt;
    }
    if (!has_i && !has_k) {
      task.checker().error(task.child_pointer("interval"),
                           allow_keyframes ? "required key is missing (give \"interval\" or \"keyframes\")"
                                           : "required key is missing");
      return std::nullopt;
    }
    IntervalsSpec iv;
    if (has_i) {
      const Node in = task["interval"];
      iv.pointer = in.pointer();
      if (!in.expect_object({"t_start", "t_end"})) return std::nullopt;
      const auto ts = in.number("t_start", true);
      const auto te = in.number("t_end", true);
      if (!ts || !te) return std::nullopt;
      if (!(*te > *ts)) {
        in.checker().error(in.child_pointer("t_end"), "t_end must be after t_start");
        return std::nullopt;
      }
      iv.form = IntervalsSpec::Form::Interval;
      iv.times = {*ts, *te};
      return iv;
    }
    const Node kn = task["keyframes"];
    iv.pointer = kn.pointer();
    if (kn.is_array()) {
      if (kn.size() < 2) {
        kn.fail("expected at least 2 keyframe times");
        return std::nullopt;
      }
      if (kn.size() > kMaxKeyframes) {
        kn.fail("too many keyframes (more than 1e7, the limit of one task)");
        return std::nullopt;
      }
      auto ts = kn.number_list(2);
      if (!ts) return std::nullopt;
      for (std::size_t i = 1; i < ts->size(); ++i)
        if (!((*ts)[i] > (*ts)[i - 1])) {
          kn[i].fail("keyframe times must be strictly increasing");
          return std::nullopt;
        }
      iv.form = IntervalsSpec::Form::Array;
      iv.times = std::move(*ts);
      return iv;
    }
    if (kn.is_object()) {
      kn.expect_object({"start", "end", "step"});
      const auto a = kn.number("start", true), b = kn.number("end", true), h = kn.number("step", true);
      if (!a || !b || !h) return std::nullopt;
      if (!(*h > 0.0)) {
        kn.checker().error(kn.child_pointer("step"), "expected a positive step");
        return std::nullopt;
      }
      if (!(*b > *a)) {
        kn.checker().error(kn.child_pointer("end"), "end must be after start");
        return std::nullopt;
      }
      if (auto problem = GenerateKeyframes(*a, *b, *h, iv)) {
        kn.checker().error(kn.child_pointer("step"), *problem);
        return std::nullopt;
      }
      return iv;
    }
    kn.fail("expected an array of keyframe times or {\"start\", \"end\", \"step\"}, found " + TypeName(kn.value()));
    return std::nullopt;
  }

  /// The type of the earlier task `name`, or nothing.
  const std::string* Earlier(const std::string& name) const {
    const auto it = earlier.find(name);
    return it == earlier.end() ? nullptr : &it->second;
  }

  void Remember(const std::string& name, const std::string& type) {
    earlier.emplace(name, type);
    if (type != "preintegrate") return;
    ++preintegrate_count;
    if (preintegrate_names.size() < 5) preintegrate_names.push_back(name);
  }

  std::optional<MeasurementsSpec> Measurements(const Node& task) {
    const auto n = task.get("measurements", true);
    if (!n) return std::nullopt;
    MeasurementsSpec m;
    m.pointer = n->pointer();
    if (n->value().is_string()) {
      const std::string name = n->value().get<std::string>();
      const std::string* type = Earlier(name);
      if (!type) {
        std::string known;
        for (const auto& e : preintegrate_names) known += (known.empty() ? "" : ", ") + Quoted(e);
        if (preintegrate_count > preintegrate_names.size())
          known += " and " + std::to_string(preintegrate_count - preintegrate_names.size()) + " more";
        n->fail("no earlier preintegrate task named " + Quoted(name) +
                (known.empty() ? std::string(" (there is none before this task)") : " (earlier ones: " + known + ")"));
        return std::nullopt;
      }
      if (*type != "preintegrate") {
        n->fail("task " + Quoted(name) + " is a " + *type + " task; measurements come from a preintegrate task");
        return std::nullopt;
      }
      m.task = name;
      return m;
    }
    if (n->is_object()) {
      if (!n->expect_object({"file"})) return std::nullopt;
      if (auto f = n->string("file", true)) {
        m.file = Resolve(base_dir, *f);
        return m;
      }
      return std::nullopt;
    }
    n->fail("expected the name of an earlier preintegrate task or {\"file\": PATH}, found " + TypeName(n->value()));
    return std::nullopt;
  }

  std::optional<std::string> Id(const Node& task, const char* key, bool required, std::string* pointer = nullptr) {
    if (pointer) *pointer = task.child_pointer(key);
    auto s = task.string(key, required);
    if (s && s->empty()) {
      task.checker().error(task.child_pointer(key), "expected a plugin id, found an empty string");
      return std::nullopt;
    }
    return s;
  }

  std::optional<std::size_t> Index(const Node& task) {
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

  // ---- tasks --------------------------------------------------------------------------
  void Task(const Node& n, std::vector<TaskSpec>& out) {
    static const std::vector<std::string> kTypes = {"propagate", "preintegrate", "propagate_by_preintegration",
                                                    "convert", "residual", "bias_update"};
    if (!n.is_object()) {
      n.fail("expected a task object, found " + TypeName(n.value()));
      return;
    }
    TaskSpec t;
    t.pointer = n.pointer();
    const auto type_node = n.get("type", true);
    std::optional<std::string> type;
    if (type_node) type = type_node->one_of(kTypes, "task types");
    const auto name = n.string("name", true);
    if (name) {
      if (!ValidName(*name))
        n.checker().error(n.child_pointer("name"), "expected a name of letters, digits, '_', '-' and '.', found '" + *name + "'");
      else if (Earlier(*name))
        n.checker().error(n.child_pointer("name"), "duplicate task name " + Quoted(*name));
      t.name = *name;
    }
    if (auto d = n.string("description", false)) t.description = *d;
    if (!type) {
      // Unknown type: still report unknown keys against the union of every task's keys? No:
      // the type decides the keys, so only the type error is reported.
      if (name) Remember(*name, "?");
      return;
    }
    t.type = *type;
    const auto needs_imu = [&] {
      if (!has_imu) n.checker().error(n.child_pointer("type"), "a " + *type + " task needs IMU samples: add a top-level /imu source");
    };
    const auto compare = [&](std::optional<bool>& dst) {
      if (auto b = n.boolean("compare_ground_truth", false)) {
        if (*b && !has_gt)
          n.checker().error(n.child_pointer("compare_ground_truth"), "needs a top-level /ground_truth source");
        dst = *b;
      }
    };
    if (*type == "propagate") {
      n.expect_object({"type", "name", "description", "propagator", "state_convention", "start", "interval",
                       "compare_ground_truth"});
      needs_imu();
      PropagateTask p;
      if (auto s = Id(n, "propagator", true)) p.propagator = *s;
      if (auto s = Id(n, "state_convention", false)) p.convention = *s;
      Start(n, p.start, p.cov);
      if (auto iv = Intervals(n, false)) p.interval = *iv;
      compare(p.compare_gt);
      t.body = p;
    } else if (*type == "preintegrate") {
      n.expect_object({"type", "name", "description", "method", "conventions", "bias", "interval", "keyframes"});
      needs_imu();
      PreintegrateTask p;
      if (auto mn = n.get("method", true)) {
        p.method_pointer = mn->pointer();
        if (mn->expect_object({"propagator", "preintegrator"})) {
          if (mn->has("propagator") && mn->has("preintegrator"))
            mn->fail("give either \"propagator\" (preintegration by propagation) or \"preintegrator\" (native), not both");
          else if (mn->has("propagator")) {
            if (auto s = Id(*mn, "propagator", true, &p.method_pointer)) p.method_id = *s;
          } else if (mn->has("preintegrator")) {
            p.native = true;
            if (auto s = Id(*mn, "preintegrator", true, &p.method_pointer)) p.method_id = *s;
          } else {
            mn->checker().error(mn->child_pointer("propagator"),
                                "required key is missing (give \"propagator\" or \"preintegrator\")");
          }
        }
      }
      if (auto cn = n.get("conventions", false)) {
        p.conventions_pointer = cn->pointer();
        if (auto l = cn->string_list(true)) p.conventions = *l;
      }
      if (auto bn = n.get("bias", false))
        if (auto b = Bias(*bn)) p.bias = *b;
      if (auto iv = Intervals(n, true)) p.intervals = *iv;
      t.body = p;
    } else if (*type == "propagate_by_preintegration") {
      n.expect_object({"type", "name", "description", "measurements", "state_convention", "start", "chain",
                       "compare_ground_truth"});
      PropByPreintTask p;
      if (auto m = Measurements(n)) p.meas = *m;
      if (auto s = Id(n, "state_convention", false)) p.convention = *s;
      Start(n, p.start, p.cov);
      p.chain = !p.start.ground_truth;
      if (auto b = n.boolean("chain", false)) p.chain = *b;
      compare(p.compare_gt);
      t.body = p;
    } else if (*type == "convert") {
      n.expect_object({"type", "name", "description", "what", "from", "to", "state", "state_end", "increment", "matrix",
                       "source"});
      ConvertTask p;
      if (auto wn = n.get("what", true)) {
        if (auto w = wn->one_of({"state_jacobian", "state_covariance", "state_transition", "increment_jacobian",
                                 "increment_covariance"})) {
          p.what_name = *w;
          using W = ConvertTask::What;
          p.what = *w == "state_jacobian"         ? W::StateJacobian
                   : *w == "state_covariance"     ? W::StateCovariance
                   : *w == "state_transition"     ? W::StateTransition
                   : *w == "increment_jacobian"   ? W::IncrementJacobian
                                                  : W::IncrementCovariance;
        }
      }
      p.from_pointer = n.child_pointer("from");
      p.to_pointer = n.child_pointer("to");
      p.source_pointer = n.child_pointer("source");
      if (auto s = Id(n, "from", !n.has("source"))) p.from = *s;
      if (auto s = Id(n, "to", true)) p.to = *s;
      if (auto sn = n.get("source", false)) {
        if (sn->expect_object({"task", "index"})) {
          if (auto tn = sn->string("task", true)) {
            if (!Earlier(*tn))
              sn->checker().error(sn->child_pointer("task"), "no earlier task named " + Quoted(*tn));
            else
              p.source_task = *tn;
          }
          if (auto in = sn->get("index", false))
            if (auto i = in->integer()) {
              if (*i < 0)
                in->fail("expected an index >= 0");
              else
                p.source_index = static_cast<std::size_t>(*i);
            }
        }
      }
      if (auto sn = n.get("state", false))
        if (auto x = StateFromJson(*sn)) p.state = *x;
      if (auto sn = n.get("state_end", false))
        if (auto x = StateFromJson(*sn)) p.state_end = *x;
      if (auto in = n.get("increment", false))
        if (auto d = IncrementFromJson(*in)) p.increment = *d;
      if (auto mn = n.get("matrix", false))
        if (auto m = Matrix15FromJson(*mn)) {
          // A covariance must be one; a transition matrix need not be symmetric.
          using W = ConvertTask::What;
          const bool cov = !p.what_name.empty() && (p.what == W::StateCovariance || p.what == W::IncrementCovariance);
          if (!cov || CheckCovarianceInput(n.checker(), mn->pointer(), m->m))
            p.matrix = std::make_shared<const Matrix15In>(std::move(*m));
        }
      // What each kind needs when there is no source.
      if (!n.has("source") && !p.what_name.empty()) {
        using W = ConvertTask::What;
        const bool state_kind = p.what == W::StateJacobian || p.what == W::StateCovariance || p.what == W::StateTransition;
        if (state_kind && !n.has("state")) n.checker().error(n.child_pointer("state"), "required key is missing (or give \"source\")");
        if (!state_kind && !n.has("increment"))
          n.checker().error(n.child_pointer("increment"), "required key is missing (or give \"source\")");
        if (p.what == W::StateTransition && !n.has("state_end"))
          n.checker().error(n.child_pointer("state_end"), "required key is missing (or give \"source\")");
        if ((p.what == W::StateCovariance || p.what == W::StateTransition || p.what == W::IncrementCovariance) &&
            !n.has("matrix"))
          n.checker().error(n.child_pointer("matrix"), "required key is missing (or give \"source\")");
      }
      if (n.has("source"))
        for (const char* k : {"state", "state_end", "increment", "matrix"})
          if (n.has(k)) n.checker().error(n.child_pointer(k), "not allowed together with \"source\" (it comes from the source task)");
      t.body = p;
    } else if (*type == "residual") {
      n.expect_object({"type", "name", "description", "kind", "measurements", "state_convention", "start", "end", "index"});
      ResidualTask p;
      if (auto kn = n.get("kind", true))
        if (auto k = kn->one_of({"gtsam", "forster"})) {
          p.kind_name = *k;
          p.kind = *k == "gtsam" ? ResidualKind::Gtsam : ResidualKind::Forster;
        }
      if (auto m = Measurements(n)) p.meas = *m;
      if (auto s = Id(n, "state_convention", false)) p.convention = *s;
      p.index = Index(n);
      for (auto [key, dst] : {std::pair<const char*, StateSpec*>{"start", &p.start}, {"end", &p.end}}) {
        if (auto sn = n.get(key, false)) {
          if (auto s = State(*sn)) *dst = *s;
        } else if (has_gt) {
          dst->ground_truth = true;
          dst->pointer = n.child_pointer(key);
        } else {
          n.checker().error(n.child_pointer(key), "required key is missing (there is no /ground_truth to default to)");
        }
      }
      t.body = p;
    } else if (*type == "bias_update") {
      n.expect_object({"type", "name", "description", "measurements", "bias", "first_order_charts", "reintegrate", "index"});
      BiasUpdateTask p;
      if (auto m = Measurements(n)) p.meas = *m;
      p.index = Index(n);
      if (auto bn = n.get("bias", true)) {
        if (bn->expect_object({"bg", "ba", "delta_bg", "delta_ba"})) {
          const bool abs = bn->has("bg") || bn->has("ba"), rel = bn->has("delta_bg") || bn->has("delta_ba");
          if (abs && rel) {
            bn->fail("give either bg/ba (the new bias) or delta_bg/delta_ba (a change of each measurement's bias), not both");
          } else if (rel) {
            p.relative = true;
            if (auto v = bn->vec3("delta_bg", false)) p.bg = *v;
            if (auto v = bn->vec3("delta_ba", false)) p.ba = *v;
          } else if (abs) {
            if (auto v = bn->vec3("bg", true)) p.bg = *v;
            if (auto v = bn->vec3("ba", true)) p.ba = *v;
          } else {
            bn->checker().error(bn->child_pointer("bg"), "required key is missing (give bg and ba, or delta_bg/delta_ba)");
          }
        }
      }
      p.charts = {"preint_reference"};
      p.charts_pointer = n.child_pointer("first_order_charts");
      if (auto cn = n.get("first_order_charts", false))
        if (auto l = cn->string_list(true)) p.charts = *l;
      if (auto b = n.boolean("reintegrate", false)) p.reintegrate = *b;
      if (p.reintegrate && !p.meas.file.empty())
        n.checker().error(n.child_pointer("reintegrate"),
                          "re-integration needs the IMU samples of a preintegrate task; measurements from a file "
                          "can only be corrected to first order (set \"reintegrate\": false)");
      t.body = p;
    }
    if (name) Remember(*name, *type);
    out.push_back(std::move(t));
  }
};

}  // namespace

std::unique_ptr<PipelineSpec> ParseSpec(const json& doc, const std::string& file, const std::string& base_dir) {
  auto spec = std::make_unique<PipelineSpec>();
  spec->file = file;
  spec->base_dir = base_dir;
  Checker c(file);
  const Node root(doc, "", c);
  if (!root.expect_object({"$schema", "description", "plugin_dirs", "allow_plugin_override", "gravity", "noise", "imu",
                           "ground_truth", "output", "omit", "tasks"}))
    c.throw_if_errors();
  Parser parser{c, base_dir, false, false, {}, {}, 0};
  if (auto d = root.string("description", false)) spec->description = *d;
  root.string("$schema", false);
  if (auto pn = root.get("plugin_dirs", false))
    if (auto l = pn->string_list(true))
      for (const auto& d : *l) spec->plugin_dirs.push_back(Resolve(base_dir, d));
  if (auto b = root.boolean("allow_plugin_override", false)) spec->allow_plugin_override = *b;
  // A pipeline (perhaps someone else's) may only write inside its own directory; -o, typed by
  // the user, is not restricted. Lexical check: a symbolic link inside the directory is trusted.
  if (auto o = root.string("output", false)) {
    const fs::path rel = fs::path(*o).lexically_normal();
    if (o->empty() || o->find('\0') != std::string::npos || rel.is_absolute() || rel.has_root_name() ||
        rel.has_root_directory() || (!rel.empty() && *rel.begin() == ".."))
      c.error("/output",
              "expected a relative path inside the pipeline's directory (not absolute, not leading out of it with "
              "'..'); to write anywhere else, give the output on the command line with -o");
    else
      spec->output = Resolve(base_dir, *o);
  }
  if (auto on = root.get("omit", false)) {
    if (!on->is_array()) {
      on->fail("expected an array of names (Phi, cov, J_bias, R, reference), found " + TypeName(on->value()));
    } else {
      std::vector<std::string> seen;
      for (std::size_t i = 0; i < on->size(); ++i) {
        const auto what = (*on)[i].one_of({"Phi", "cov", "J_bias", "R", "reference"});
        if (!what) continue;
        if (std::find(seen.begin(), seen.end(), *what) != seen.end()) (*on)[i].fail("'" + *what + "' is listed twice");
        seen.push_back(*what);
        OmitSpec& o = spec->omit;
        if (*what == "Phi") o.Phi = true;
        if (*what == "cov") o.cov = true;
        if (*what == "J_bias") o.J_bias = true;
        if (*what == "R") o.R = true;
        if (*what == "reference") o.reference = true;
      }
    }
  }
  if (auto g = root.vec3("gravity", false)) spec->gravity = *g;
  if (auto nn = root.get("noise", true))
    if (auto q = NoiseFromJson(*nn)) spec->noise = *q;
  if (auto in = root.get("imu", false)) {
    parser.has_imu = true;
    spec->imu = parser.Imu(*in);
  }
  if (auto gn = root.get("ground_truth", false)) {
    parser.has_gt = true;
    if (gn->expect_object({"format", "path", "max_gap_factor", "allow_gaps"})) {
      if (auto fn = gn->get("format", true)) fn->one_of({"euroc"});
      GroundTruthSpec g;
      g.pointer = gn->pointer();
      g.timing = Parser::Timing(*gn);
      if (auto p = gn->string("path", true)) g.path = Resolve(base_dir, *p);
      spec->gt = g;
    }
    if (!root.has("imu"))
      c.error(gn->pointer(), "ground truth is put on the IMU data's time axis: add a top-level /imu source");
  }
  if (auto tn = root.get("tasks", true)) {
    if (!tn->is_array() || tn->size() == 0) {
      tn->fail("expected a non-empty array of tasks, found " + (tn->is_array() ? std::string("an empty array") : TypeName(tn->value())));
    } else {
      spec->tasks.reserve(tn->size());  // a TaskSpec is ~3 KB: no reallocation copies
      for (std::size_t i = 0; i < tn->size(); ++i) parser.Task((*tn)[i], spec->tasks);
    }
  }
  c.throw_if_errors();
  return spec;
}

// ---- Pipeline ---------------------------------------------------------------------------
Pipeline::Pipeline(std::unique_ptr<PipelineSpec> s) : spec_(std::move(s)) {}
Pipeline::Pipeline(Pipeline&&) noexcept = default;
Pipeline& Pipeline::operator=(Pipeline&&) noexcept = default;
Pipeline::~Pipeline() = default;

Pipeline Pipeline::Load(const std::string& path) {
  const json doc = ParseJsonFile(path);
  const std::string base = fs::path(path).parent_path().string();
  return FromJson(doc, path, base.empty() ? "." : base);
}

Pipeline Pipeline::FromJson(const json& doc, const std::string& file, const std::string& base_dir) {
  return Pipeline(ParseSpec(doc, file, base_dir));
}

const std::string& Pipeline::file() const { return spec_->file; }
const std::vector<std::string>& Pipeline::plugin_dirs() const { return spec_->plugin_dirs; }
const std::optional<std::string>& Pipeline::output_path() const { return spec_->output; }

std::vector<std::string> Pipeline::input_files() const {
  std::vector<std::string> files;
  std::unordered_set<std::string> seen;  // linear in the number of tasks
  const auto add = [&](const std::string& f) {
    if (!f.empty() && seen.insert(f).second) files.push_back(f);
  };
  add(spec_->file);
  if (spec_->imu && spec_->imu->format != ImuSourceSpec::Format::Inline) add(spec_->imu->path);
  if (spec_->gt) add(spec_->gt->path);
  for (const auto& t : spec_->tasks) {
    if (const auto* x = std::get_if<PropByPreintTask>(&t.body)) add(x->meas.file);
    if (const auto* x = std::get_if<ResidualTask>(&t.body)) add(x->meas.file);
    if (const auto* x = std::get_if<BiasUpdateTask>(&t.body)) add(x->meas.file);
  }
  return files;
}

}  // namespace imuconv::pipeline
