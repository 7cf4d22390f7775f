// "bias_update": measurements corrected to a new bias estimate to first order in one or more
// bias-Jacobian charts, and (for a preintegrate task's measurements) compared with
// re-integrating the samples with that bias.
#include "../forms/comparison.h"
#include "../forms/increment.h"
#include "../forms/state.h"
#include "../io/message_text.h"
#include "context.h"
#include "plugins_used.h"
#include "task.h"

namespace imuconv::pipeline {
namespace {

class BiasUpdateTask : public Task {
 public:
  MeasurementsSpec meas;
  bool relative = false;  // delta_bg/delta_ba rather than bg/ba
  Vec3 bg = Vec3::Zero(), ba = Vec3::Zero();
  std::vector<std::string> charts;  // first-order correction charts
  std::string charts_pointer;
  bool reintegrate = true;
  std::optional<std::size_t> index;

  const MeasurementsSpec* measurements() const override { return &meas; }

  void plugins_used(PluginUse& use) const override {
    for (const auto& c : charts) use.increment(c);
    use.measurements();
  }

  void check_plugins(RunContext& ctx, Checker& c) const override {
    for (std::size_t i = 0; i < charts.size(); ++i)
      ctx.check_id(c, PluginKind::IncrementConvention, charts[i],
                   charts_pointer + "/" + std::to_string(i));
  }

  /// The largest differences between the first-order corrections and re-integration.
  struct MaxErrors {
    double rot = 0, dp = 0, dv = 0;
  };

  /// "first_order": {CHART: {"delta", "vs_reintegrated"?}} of one measurement.
  void write_first_order(const RunContext& ctx, JsonWriter& w, const MeasRecord& r, const Vec3& nbg,
                         const Vec3& nba, const std::optional<Preintegrated>& re,
                         MaxErrors& max) const {
    w.key("first_order");
    w.begin_object();
    for (const auto& c : charts) {
      const PreintIncrement d = BiasCorrectedDelta(ctx.reg, r.m, c, nbg, nba);
      w.key(c);
      w.begin_object();
      w.key("delta");
      WriteIncrement(w, d, !ctx.spec.omit.R);
      if (re) {
        const double rot = RotationErrorDeg(re->delta.dR, d.dR);
        const double edp = (re->delta.dp - d.dp).norm(), edv = (re->delta.dv - d.dv).norm();
        w.key("vs_reintegrated");
        w.begin_object();
        w.key("rotation_deg");
        w.number(rot);
        w.key("dp_m");
        w.number(edp);
        w.key("dv_mps");
        w.number(edv);
        w.end_object();
        max.rot = std::max(max.rot, rot);
        max.dp = std::max(max.dp, edp);
        max.dv = std::max(max.dv, edv);
      }
      w.end_object();
    }
    w.end_object();
  }

  void run(RunContext& ctx, JsonWriter& w, TaskResult&) const override {
    const auto& ms = ctx.measurements(meas);
    const auto sel = ctx.select(ms, index, pointer, MeasurementsName(meas));
    // Measurements of a preintegrate task can be integrated again, as that task did.
    const auto* origin = meas.task.empty() ? nullptr : &ctx.results.at(meas.task).reintegrate;
    WriteMeasurementsSource(w, meas);
    w.key("updates");
    w.begin_array();
    MaxErrors max;
    for (std::size_t k : sel) {
      const MeasRecord& r = ms[k];
      const Vec3 nbg = relative ? Vec3(r.m.bg_hat + bg) : bg;
      const Vec3 nba = relative ? Vec3(r.m.ba_hat + ba) : ba;
      w.begin_object();
      w.key("index");
      w.unsigned_integer(k);
      ctx.write_times(w, r.t_s, r.t_e);
      w.key("bias_estimate");
      WriteBias(w, r.m.bg_hat, r.m.ba_hat);
      w.key("new_bias");
      WriteBias(w, nbg, nba);
      std::optional<Preintegrated> re;
      if (reintegrate && origin && r.t_s && r.t_e) {
        re = (*origin)(ctx.window(*r.t_s, *r.t_e), nbg, nba);
        w.key("reintegrated");
        MeasRecord rr;
        rr.m = *re;
        rr.t_s = r.t_s;
        rr.t_e = r.t_e;
        WriteMeasurement(w, rr, k, {}, ctx.reg, ctx.spec.omit, ctx.imu.origin);
      }
      write_first_order(ctx, w, r, nbg, nba, re, max);
      w.end_object();
    }
    w.end_array();
    if (std::ostream* o = ctx.summary()) {
      *o << "bias_update '" << name << "': " << sel.size() << " measurement(s), first order in "
         << Join(charts);
      if (reintegrate && origin)
        *o << "; first order vs re-integration: max " << Num(max.rot, 3) << " deg, "
           << Num(max.dp, 3) << " m (dp), " << Num(max.dv, 3) << " m/s (dv)";
      *o << "\n";
    }
  }
};

void ReadNewBias(const Node& bn, BiasUpdateTask& p) {
  if (!bn.expect_object({"bg", "ba", "delta_bg", "delta_ba"})) return;
  const bool abs = bn.has("bg") || bn.has("ba"), rel = bn.has("delta_bg") || bn.has("delta_ba");
  if (abs && rel) {
    bn.fail(
        "give either bg/ba (the new bias) or delta_bg/delta_ba (a change of each measurement's "
        "bias), not both");
  } else if (rel) {
    p.relative = true;
    if (auto v = bn.vec3("delta_bg", false)) p.bg = *v;
    if (auto v = bn.vec3("delta_ba", false)) p.ba = *v;
  } else if (abs) {
    if (auto v = bn.vec3("bg", true)) p.bg = *v;
    if (auto v = bn.vec3("ba", true)) p.ba = *v;
  } else {
    bn.checker().error(bn.child_pointer("bg"),
                       "required key is missing (give bg and ba, or delta_bg/delta_ba)");
  }
}

}  // namespace

std::unique_ptr<Task> ParseBiasUpdate(const ParseContext& ctx, const Node& n) {
  n.expect_object({"type", "name", "description", "measurements", "bias", "first_order_charts",
                   "reintegrate", "index"});
  auto p = NewMeasurementsTask<BiasUpdateTask>(ctx, n);
  p->index = ReadIndex(n);
  if (auto bn = n.get("bias", true)) ReadNewBias(*bn, *p);
  p->charts = {"preint_reference"};
  p->charts_pointer = n.child_pointer("first_order_charts");
  if (auto cn = n.get("first_order_charts", false))
    if (auto l = cn->distinct_string_list(true)) p->charts = *l;
  if (auto b = n.boolean("reintegrate", false)) p->reintegrate = *b;
  if (p->reintegrate && !p->meas.file.empty())
    n.checker().error(
        n.child_pointer("reintegrate"),
        "re-integration needs the IMU samples of a preintegrate task; measurements from a file "
        "can only be corrected to first order (set \"reintegrate\": false)");
  return p;
}

}  // namespace imuconv::pipeline
