// "residual": the residual of a measurement between two states, with its Jacobians and
// squared Mahalanobis distance. Two output forms:
//  - kinds "gtsam" and "forster" (the bridge's generic Residual): r, H_start, H_end and
//    H_increment in charts imuconv names, the Jacobians in the task's state convention;
//  - any other kind is a residual plugin's id (residual_factor.h; plugins/residuals/): the
//    system's own factor, in its own layout and parameter increments, as its optimizer
//    receives it. Its Jacobians are not w.r.t. a 15-dof state chart (VINS's 15x7 pose blocks
//    with a zero q.w column, Basalt's 9-dof states without biases), so forcing them into
//    Residual's 15x15 H_start/H_end would either invent a chart or drop what makes them the
//    system's; the plugin writes them under its own names (ResidualJsonSink), after its
//    "layout", and "state_convention" does not apply to them.
// A plugin's measurement is expressed in the plugin's increment convention first, so a
// measurement from any preintegrator can be judged by any system's factor.
#include <Eigen/Cholesky>
#include <cmath>

#include "../forms/chart_matrix.h"
#include "../forms/state.h"
#include "../io/message_text.h"
#include "context.h"
#include "imuconv/did_you_mean.h"
#include "imuconv/printable.h"
#include "plugins_used.h"
#include "residual_json_sink.h"
#include "task.h"

namespace imuconv::pipeline {
namespace {

/// Whether `kind` names one of the registry's generic residuals rather than a plugin.
std::optional<ResidualKind> GenericKind(const std::string& kind) {
  if (kind == "gtsam") return ResidualKind::Gtsam;
  if (kind == "forster") return ResidualKind::Forster;
  return std::nullopt;
}

/// r^T cov^-1 r when cov is positive definite.
template <int N>
std::optional<double> Mahalanobis(const Eigen::Matrix<double, N, 1>& r,
                                  const Eigen::Matrix<double, N, N>& cov) {
  const Eigen::LDLT<Eigen::Matrix<double, N, N>> ldlt(cov);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || !(ldlt.vectorD().minCoeff() > 0.0))
    return std::nullopt;
  return r.dot(ldlt.solve(r));
}

class ResidualTask : public Task {
 public:
  /// Set for kinds gtsam and forster; a residual plugin's id otherwise.
  std::optional<ResidualKind> generic;
  std::string kind_name;
  MeasurementsSpec meas;
  std::string convention = "left";
  StateSpec start, end;
  std::optional<std::size_t> index;

  const MeasurementsSpec* measurements() const override { return &meas; }

  void plugins_used(PluginUse& use) const override {
    if (generic) {
      use.state(convention);
    } else {
      use.add(PluginKind::Residual, kind_name);
      if (use.registry().has(PluginKind::Residual, kind_name))
        use.increment(use.registry().info(PluginKind::Residual, kind_name).native_convention);
    }
    use.measurements();
  }

  void check_plugins(RunContext& ctx, Checker& c) const override {
    if (generic) {
      ctx.check_id(c, PluginKind::StateConvention, convention, pointer + "/state_convention");
      return;
    }
    const std::string at = pointer + "/kind";
    if (!ctx.reg.has(PluginKind::Residual, kind_name)) {
      std::vector<std::string> known = {"gtsam", "forster"};
      for (const auto& id : ctx.reg.ids(PluginKind::Residual)) known.push_back(id);
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      c.error(at, "unknown residual kind " + Quoted(kind_name) + DidYouMean(kind_name, known) +
                      "; known: " + list + " (gtsam and forster, or a residual plugin's id)");
      return;
    }
    // The measurement is expressed in the plugin's increment convention.
    ctx.check_id(c, PluginKind::IncrementConvention,
                 ctx.reg.info(PluginKind::Residual, kind_name).native_convention, at);
  }

  ImuState state_at(const RunContext& ctx, const StateSpec& s, std::optional<double> t,
                    const char* which) const {
    if (!s.ground_truth) return s.x;
    if (!t)
      ctx.fail(s.pointer, std::string("ground truth needs the measurement's ") + which + " time");
    return ctx.gt_at(*t, s.pointer);
  }

  /// One residual of a plugin: its own names under its kind, written by the plugin through
  /// ResidualJsonSink; its squared Mahalanobis distance when it gives one.
  std::optional<double> run_plugin(RunContext& ctx, JsonWriter& w, const MeasRecord& r,
                                   const ImuState& xs, const ImuState& xe,
                                   const std::string& at) const {
    const auto factor = ctx.reg.residual_factor(kind_name);
    const Preintegrated m = Express(ctx.reg, r.m, factor_convention(ctx));
    w.key(kind_name);
    w.begin_object();
    ResidualJsonSink sink(w);
    const Status st = factor->evaluate(m, xs, xe, ctx.spec.gravity, sink);
    const std::string who = "residual plugin " + Quoted(kind_name) + " (" +
                            Printable(ctx.reg.info(PluginKind::Residual, kind_name).file) + ")";
    if (!st.ok()) ctx.fail(at, who + ": " + Printable(st.message()));
    if (const std::string problem = sink.problem(); !problem.empty())
      ctx.fail(at, who + " " + problem + "; no output is written");
    w.end_object();
    return sink.distance();
  }

  const std::string& factor_convention(const RunContext& ctx) const {
    return ctx.reg.info(PluginKind::Residual, kind_name).native_convention;
  }

  /// One residual of kind gtsam or forster: the generic form, Jacobians in `convention`.
  std::optional<double> run_generic(RunContext& ctx, JsonWriter& w, const MeasRecord& r,
                                    const ImuState& xs, const ImuState& xe) const {
    static const std::vector<std::string> rblocks = {"theta", "p", "v", "bg", "ba"};
    const std::string rconv = "residual_" + kind_name;
    const auto& sb = ctx.blocks(PluginKind::StateConvention, convention);
    const auto& ib = ctx.blocks(PluginKind::IncrementConvention, "preint_reference");
    const Residual res =
        ComputeResidual(ctx.reg, *generic, r.m, xs, xe, convention, ctx.spec.gravity);
    w.key("r");
    WriteChartVector(w, res.r, rconv, rblocks);
    w.key("H_start");
    WriteMixed(w, res.H_start, rconv, rblocks, convention, sb);
    w.key("H_end");
    WriteMixed(w, res.H_end, rconv, rblocks, convention, sb);
    w.key("H_increment");
    WriteMixed(w, res.H_increment, rconv, rblocks, "preint_reference", ib);
    w.key("cov");
    WriteCovariance(w, res.cov, rconv, rblocks);
    return Mahalanobis<15>(res.r, res.cov);
  }

  void run(RunContext& ctx, JsonWriter& w, TaskResult&) const override {
    const auto& ms = ctx.measurements(meas);
    const auto sel = ctx.select(ms, index, pointer, MeasurementsName(meas));
    if ((!start.ground_truth || !end.ground_truth) && sel.size() > 1)
      ctx.fail(pointer, "explicit start/end states go with one measurement; give \"index\" (" +
                            MeasurementsName(meas) + " has " + std::to_string(ms.size()) + ")");
    w.key("kind");
    w.string(kind_name);
    WriteMeasurementsSource(w, meas);
    if (generic) {
      w.key("state_convention");
      w.string(convention);
    } else {
      w.key("layout");
      w.string(ctx.reg.info(PluginKind::Residual, kind_name).layout);
    }
    w.key("residuals");
    w.begin_array();
    double sum_m2 = 0;
    std::size_t n_m2 = 0;
    for (std::size_t k : sel) {
      const MeasRecord& r = ms[k];
      const ImuState xs = state_at(ctx, start, r.t_s, "start"),
                     xe = state_at(ctx, end, r.t_e, "end");
      w.begin_object();
      w.key("index");
      w.unsigned_integer(k);
      ctx.write_times(w, r.t_s, r.t_e);
      w.key("x_s");
      WriteState(w, xs);
      w.key("x_e");
      WriteState(w, xe);
      const std::optional<double> m2 =
          generic ? run_generic(ctx, w, r, xs, xe)
                  : run_plugin(ctx, w, r, xs, xe, pointer + "/residuals/" + std::to_string(k));
      if (m2) {
        w.key("mahalanobis_squared");
        w.number(*m2);
        sum_m2 += *m2;
        ++n_m2;
      }
      w.end_object();
    }
    w.end_array();
    if (n_m2) {
      w.key("mean_mahalanobis_squared");
      w.number(sum_m2 / static_cast<double>(n_m2));
    }
    if (std::ostream* o = ctx.summary()) {
      *o << "residual '" << name << "' (" << kind_name << "): " << sel.size() << " residual(s)";
      if (n_m2)
        *o << ", mean r^T cov^-1 r = " << Num(sum_m2 / static_cast<double>(n_m2), 4) << " ("
           << (generic ? 15 : ctx.reg.info(PluginKind::Residual, kind_name).degrees_of_freedom)
           << " dof)";
      *o << "\n";
    }
  }
};

}  // namespace

std::unique_ptr<Task> ParseResidual(const ParseContext& ctx, const Node& n) {
  n.expect_object({"type", "name", "description", "kind", "measurements", "state_convention",
                   "start", "end", "index"});
  auto p = std::make_unique<ResidualTask>();
  // gtsam, forster or a residual plugin's id (checked against the registry in check_plugins).
  const std::optional<std::string> kind = ReadPluginId(n, "kind", true);
  if (kind) {
    p->kind_name = *kind;
    p->generic = GenericKind(*kind);
  }
  if (auto m = ReadMeasurementsSpec(ctx, n)) p->meas = *m;
  if (auto s = ReadPluginId(n, "state_convention", false)) {
    p->convention = *s;
    if (kind && !p->generic)
      n.checker().error(
          n.child_pointer("state_convention"),
          "does not apply to kind '" + p->kind_name +
              "': its Jacobians are w.r.t. the system's own parameter increments (see the output's "
              "\"layout\"); give state_convention with kind gtsam or forster only");
  }
  p->index = ReadIndex(n);
  for (auto [key, dst] :
       {std::pair<const char*, StateSpec*>{"start", &p->start}, {"end", &p->end}}) {
    if (auto sn = n.get(key, false)) {
      if (auto s = ReadStateSpec(ctx, *sn)) *dst = *s;
    } else if (ctx.has_gt) {
      dst->ground_truth = true;
      dst->pointer = n.child_pointer(key);
    } else {
      n.checker().error(n.child_pointer(key),
                        "required key is missing (there is no /ground_truth to default to)");
    }
  }
  return p;
}

}  // namespace imuconv::pipeline
