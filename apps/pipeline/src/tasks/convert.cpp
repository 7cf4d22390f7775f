// "convert": one conversion between two conventions of a kind: a state Jacobian, covariance
// or transition matrix, or an increment Jacobian or covariance, of given values or of an
// earlier task's result ("source").
#include "../forms/chart_matrix.h"
#include "../forms/increment.h"
#include "../forms/input_checks.h"
#include "../forms/state.h"
#include "context.h"
#include "imuconv/printable.h"
#include "plugins_used.h"
#include "task.h"

namespace imuconv::pipeline {
namespace {

constexpr const char* kRef = "preint_reference";

class ConvertTask : public Task {
 public:
  enum class What {
    StateJacobian,
    StateCovariance,
    StateTransition,
    IncrementJacobian,
    IncrementCovariance
  } what{};
  std::string what_name;
  std::optional<std::string> from;
  std::string to;
  std::optional<ImuState> state, state_end;
  std::optional<PreintIncrement> increment;
  std::shared_ptr<const Matrix15In> matrix;  // by pointer, as CovSpec
  std::optional<std::string> source_task;
  std::size_t source_index = 0;
  std::string from_pointer, to_pointer, source_pointer;

  bool state_kind() const {
    return what == What::StateJacobian || what == What::StateCovariance ||
           what == What::StateTransition;
  }
  bool covariance() const {
    return what == What::StateCovariance || what == What::IncrementCovariance;
  }
  PluginKind kind() const {
    return state_kind() ? PluginKind::StateConvention : PluginKind::IncrementConvention;
  }

  void references(
      const std::function<void(const std::string&, const std::string&)>& f) const override {
    if (source_task) f(*source_task, source_pointer + "/task");
  }

  void plugins_used(PluginUse& use) const override {
    const auto conv = [&](const std::string& id) {
      state_kind() ? use.state(id) : use.increment(id);
    };
    if (from) conv(*from);
    conv(to);
    if (matrix && matrix->convention) conv(*matrix->convention);
    if (!state_kind()) use.measurements();
  }

  void check_plugins(RunContext& ctx, Checker& c) const override {
    if (from) ctx.check_id(c, kind(), *from, from_pointer);
    ctx.check_id(c, kind(), to, to_pointer);
    if (matrix && matrix->convention && from && *matrix->convention != *from)
      c.error(matrix->pointer + "/convention", "the matrix is in " + Quoted(*matrix->convention) +
                                                   " but \"from\" is " + Quoted(*from));
    if (matrix && from && ctx.reg.has(kind(), *from)) {
      CovSpec cs;
      cs.given = true;
      cs.in = matrix;
      ctx.check_cov_convention(c, cs, kind(), *from);
    }
    if (source_task) {
      const std::string& type = ctx.type_of(*source_task);
      const bool ok = state_kind() ? (type == "propagate" || type == "propagate_by_preintegration")
                                   : type == "preintegrate";
      if (!ok)
        c.error(source_pointer + "/task",
                "task '" + *source_task + "' is a " + type + " task; a " + what_name +
                    " conversion takes its matrix from " +
                    (state_kind() ? "a propagate or propagate_by_preintegration task"
                                  : "a preintegrate task"));
    }
  }

  /// The values to convert: given, or the source's record (whose chart then is "from").
  struct Inputs {
    std::string from;
    ImuState xs, xe;
    PreintIncrement d;
    Mat15 M = Mat15::Zero();
  };
  Inputs inputs(const RunContext& ctx) const {
    Inputs in;
    in.from = from.value_or("");
    if (!source_task) {
      if (state) in.xs = *state;
      if (state_end) in.xe = *state_end;
      if (increment) in.d = *increment;
      if (matrix) in.M = matrix->m;
      return in;
    }
    const TaskResult& src = ctx.results.at(*source_task);
    const std::size_t count = state_kind() ? src.props.size() : src.meas.size();
    if (source_index >= count)
      ctx.fail(source_pointer + "/index", "task '" + *source_task + "' has " +
                                              std::to_string(count) + " result(s); index " +
                                              std::to_string(source_index) + " is out of range");
    std::string src_conv;
    if (state_kind()) {
      const PropRecord& r = src.props[source_index];
      in.xs = r.x_s;
      in.xe = r.x_e;
      src_conv = r.convention;
      in.M = what == What::StateTransition ? r.Phi : r.cov;
    } else {
      const MeasRecord& r = src.meas[source_index];
      in.d = r.m.delta;
      in.M = r.m.cov;
      src_conv = kRef;
    }
    if (!in.from.empty() && in.from != src_conv)
      ctx.fail(from_pointer, "the source's matrices are in '" + src_conv + "', not '" + in.from +
                                 "' (leave \"from\" out to use the source's convention)");
    in.from = src_conv;
    return in;
  }

  void run(RunContext& ctx, JsonWriter& w, TaskResult&) const override {
    const Inputs in = inputs(ctx);
    const Registry& reg = ctx.reg;
    const auto& bf = ctx.blocks(kind(), in.from);
    const auto& bt = ctx.blocks(kind(), to);
    // The result first (it may throw), then the output.
    Mat15 result;
    const ImuState& x_at =
        source_task ? in.xe : in.xs;  // state Jacobian / covariance: at the source's end state
    switch (what) {
      case What::StateJacobian:
        result = reg.conversion(in.from, to, x_at);
        break;
      case What::StateCovariance:
        result = reg.convert_covariance(in.from, to, x_at, in.M);
        break;
      case What::StateTransition:
        result = reg.convert_transition(in.from, to, in.xs, in.xe, in.M);
        break;
      case What::IncrementJacobian:
        result = reg.conversion(in.from, to, in.d);
        break;
      case What::IncrementCovariance:
        result = reg.convert_covariance(in.from, to, in.d, in.M);
        break;
    }
    w.key("what");
    w.string(what_name);
    w.key("from");
    w.string(in.from);
    w.key("to");
    w.string(to);
    if (source_task) {
      w.key("source");
      w.begin_object();
      w.key("task");
      w.string(*source_task);
      w.key("index");
      w.unsigned_integer(source_index);
      w.end_object();
    }
    if (state_kind()) {
      w.key("state");
      WriteState(w, what == What::StateTransition ? in.xs : x_at);
      if (what == What::StateTransition) {
        w.key("state_end");
        WriteState(w, in.xe);
      }
    } else {
      w.key("increment");
      WriteIncrement(w, in.d, !ctx.spec.omit.R);
    }
    if (what == What::StateJacobian || what == What::IncrementJacobian) {
      w.key("result");
      WriteMixed(w, result, to, bt, in.from, bf);
    } else if (covariance()) {
      w.key("input");
      WriteCovariance(w, in.M, in.from, bf);
      w.key("result");
      WriteCovariance(w, result, to, bt);
    } else {
      w.key("input");
      WriteChart(w, in.M, in.from, bf);
      w.key("result");
      WriteChart(w, result, to, bt);
    }
    if (std::ostream* o = ctx.summary())
      *o << "convert '" << name << "': " << what_name << " from " << in.from << " to " << to
         << "\n";
  }
};

/// What each kind needs when there is no source, and what a source replaces.
void CheckGivenValues(const Node& n, const ConvertTask& p) {
  if (n.has("source")) {
    for (const char* k : {"state", "state_end", "increment", "matrix"})
      if (n.has(k))
        n.checker().error(n.child_pointer(k),
                          "not allowed together with \"source\" (it comes from the source task)");
    return;
  }
  if (p.what_name.empty()) return;
  const auto required = [&](const char* key) {
    if (!n.has(key))
      n.checker().error(n.child_pointer(key), "required key is missing (or give \"source\")");
  };
  required(p.state_kind() ? "state" : "increment");
  if (p.what == ConvertTask::What::StateTransition) required("state_end");
  if (p.what != ConvertTask::What::StateJacobian && p.what != ConvertTask::What::IncrementJacobian)
    required("matrix");
}

void ReadSource(const ParseContext& ctx, const Node& sn, ConvertTask& p) {
  if (!sn.expect_object({"task", "index"})) return;
  if (auto tn = sn.string("task", true)) {
    if (!ctx.earlier(*tn))
      sn.checker().error(sn.child_pointer("task"), "no earlier task named " + Quoted(*tn));
    else
      p.source_task = *tn;
  }
  if (auto in = sn.get("index", false))
    if (auto i = in->integer()) {
      if (*i < 0)
        in->fail("expected an index >= 0");
      else
        p.source_index = static_cast<std::size_t>(*i);
    }
}

}  // namespace

std::unique_ptr<Task> ParseConvert(const ParseContext& ctx, const Node& n) {
  n.expect_object({"type", "name", "description", "what", "from", "to", "state", "state_end",
                   "increment", "matrix", "source"});
  auto p = std::make_unique<ConvertTask>();
  using W = ConvertTask::What;
  if (auto wn = n.get("what", true)) {
    if (auto w = wn->one_of({"state_jacobian", "state_covariance", "state_transition",
                             "increment_jacobian", "increment_covariance"})) {
      p->what_name = *w;
      p->what = *w == "state_jacobian"       ? W::StateJacobian
                : *w == "state_covariance"   ? W::StateCovariance
                : *w == "state_transition"   ? W::StateTransition
                : *w == "increment_jacobian" ? W::IncrementJacobian
                                             : W::IncrementCovariance;
    }
  }
  p->from_pointer = n.child_pointer("from");
  p->to_pointer = n.child_pointer("to");
  p->source_pointer = n.child_pointer("source");
  if (auto s = ReadPluginId(n, "from", !n.has("source"))) p->from = *s;
  if (auto s = ReadPluginId(n, "to", true)) p->to = *s;
  if (auto sn = n.get("source", false)) ReadSource(ctx, *sn, *p);
  if (auto sn = n.get("state", false))
    if (auto x = StateFromJson(*sn)) p->state = *x;
  if (auto sn = n.get("state_end", false))
    if (auto x = StateFromJson(*sn)) p->state_end = *x;
  if (auto in = n.get("increment", false))
    if (auto d = IncrementFromJson(*in)) p->increment = *d;
  if (auto mn = n.get("matrix", false))
    if (auto m = Matrix15FromJson(*mn)) {
      // A covariance must be one; a transition matrix need not be symmetric.
      if (p->what_name.empty() || !p->covariance() ||
          CheckCovarianceInput(n.checker(), mn->pointer(), m->m))
        p->matrix = std::make_shared<const Matrix15In>(std::move(*m));
    }
  CheckGivenValues(n, *p);
  return p;
}

}  // namespace imuconv::pipeline
