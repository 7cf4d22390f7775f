// "preintegrate": preintegrated measurements over one interval or consecutive keyframes, by a
// propagator (preintegration by propagation, paper section 3.1) or a native preintegrator,
// expressed in any increment conventions. Intervals are independent: computed and written on
// the thread pool.
#include "../forms/state.h"
#include "../io/message_text.h"
#include "context.h"
#include "plugins_used.h"
#include "task.h"

namespace imuconv::pipeline {
namespace {

class PreintegrateTask : public Task {
 public:
  bool native = false;  // preintegrator (true) or propagator (false)
  std::string method_id, method_pointer;
  std::vector<std::string> conventions;
  std::string conventions_pointer;
  BiasSpec bias;
  IntervalsSpec keyframes;

  const IntervalsSpec* intervals() const override { return &keyframes; }
  std::size_t count() const { return keyframes.size() < 2 ? 0 : keyframes.size() - 1; }

  KeptRecords kept_records(
      const std::function<std::size_t(const MeasurementsSpec&)>&) const override {
    return {count(), sizeof(MeasRecord), "measurement"};
  }

  PluginKind kind() const { return native ? PluginKind::Preintegrator : PluginKind::Propagator; }

  void plugins_used(PluginUse& use) const override {
    const Registry& reg = use.registry();
    use.add(kind(), method_id);
    if (reg.has(kind(), method_id)) {
      const PluginInfo& info = reg.info(kind(), method_id);
      // A propagator's native chart is a state convention; a preintegrator's are increment ones.
      if (native) {
        use.increment(info.native_convention);
        use.increment(info.jacobian_convention);
      } else {
        use.state(info.native_convention);
      }
    }
    for (const auto& c : conventions) use.increment(c);
    use.measurements();
  }

  void check_plugins(RunContext& ctx, Checker& c) const override {
    ctx.check_id(c, kind(), method_id, method_pointer);
    // Resolved to its plugin (and the conventions its path needs) once, here: no lookup by
    // string per interval.
    if (ctx.reg.has(kind(), method_id)) {
      try {
        ctx.methods[this] = ResolvePreintegrationMethod(ctx.reg, kind(), method_id);
      } catch (const std::exception& e) {
        c.error(method_pointer, e.what());
      }
    }
    for (std::size_t i = 0; i < conventions.size(); ++i)
      ctx.check_id(c, PluginKind::IncrementConvention, conventions[i],
                   conventions_pointer + "/" + std::to_string(i));
  }

  void check_times(const RunContext& ctx, Checker& c) const override {
    if (keyframes.size() < 2 || !ctx.have_imu) return;  // (no /imu is reported by the parser)
    ctx.check_interval_times(c, keyframes);
    // The bias at every interval start: the ground truth spans one range, so the first and
    // the last start decide.
    if (bias.ground_truth) {
      ctx.check_gt_state(c, keyframes.front(), bias.pointer);
      if (keyframes.size() > 2) ctx.check_gt(c, keyframes.time(keyframes.size() - 2), bias.pointer);
    }
  }

  /// Interval k, from keyframe k to k + 1.
  void compute(const RunContext& ctx, const PreintegrationMethod& method, std::size_t k,
               MeasRecord& r) const {
    const double ts = keyframes.time(k), te = keyframes.time(k + 1);
    Vec3 bg = bias.bg, ba = bias.ba;
    if (bias.ground_truth) {
      const ImuState g = ctx.gt_at(ts, bias.pointer);
      bg = g.bg;
      ba = g.ba;
    }
    const SampleWindow win = ctx.window(ts, te);
    r.m = Preintegrate(ctx.reg, method, win, bg, ba, ctx.spec.noise);
    r.t_s = ts;
    r.t_e = te;
    r.n_knots = win.size();
  }

  void run(RunContext& ctx, JsonWriter& w, TaskResult& res) const override {
    const PreintegrationMethod& method = ctx.methods.at(this);
    res.reintegrate = [&ctx, &method](const SampleWindow& win, const Vec3& bg, const Vec3& ba) {
      return Preintegrate(ctx.reg, method, win, bg, ba, ctx.spec.noise);
    };
    const std::size_t n = count();
    // Every interval on its own, computed and written on the pool; its record is kept only
    // when a later task uses it.
    const bool keep = ctx.kept(name);
    if (keep) res.meas.resize(n);
    w.key("method");
    w.begin_object();
    w.key(native ? "preintegrator" : "propagator");
    w.string(method_id);
    w.end_object();
    w.key("bias");
    if (bias.ground_truth)
      w.string("ground_truth at each interval start");
    else
      WriteBias(w, bias.bg, bias.ba);
    w.key("conventions");
    w.string_list(conventions);
    w.key("measurements");
    w.begin_array();
    double total = 0;  // summed in index order, whatever the thread count
    const std::size_t window = ctx.out.window();
    std::vector<double> dts(std::min(window, n));
    ctx.out.write_elements(
        w, n,
        [&](JsonWriter& cw, std::size_t k) {
          MeasRecord local;
          MeasRecord& r = keep ? res.meas[k] : local;
          compute(ctx, method, k, r);
          WriteMeasurement(cw, r, k, conventions, ctx.reg, ctx.spec.omit, ctx.imu.origin);
          dts[k % window] = r.m.dt;
        },
        [&](std::size_t k) { total += dts[k % window]; });
    w.end_array();
    if (std::ostream* o = ctx.summary()) {
      *o << "preintegrate '" << name << "': " << n << " measurement(s) over " << Num(total)
         << " s by " << (native ? "native preintegrator " : "propagation with ") << method_id
         << (conventions.empty() ? std::string() : ", expressed in " + Join(conventions));
      const IntervalsSpec& iv = keyframes;
      if (iv.form == IntervalsSpec::Form::Generated && iv.short_last)
        *o << "; the last interval, [" << Num(iv.time(n - 1), 10) << ", " << Num(iv.end, 10)
           << "] s, is the " << Num(iv.end - iv.time(n - 1)) << " s left after " << n - 1
           << " whole step(s) of " << Num(iv.step) << " s";
      *o << "\n";
    }
  }
};

}  // namespace

std::unique_ptr<Task> ParsePreintegrate(const ParseContext& ctx, const Node& n) {
  n.expect_object(
      {"type", "name", "description", "method", "conventions", "bias", "interval", "keyframes"});
  RequireImu(ctx, n, "preintegrate");
  auto p = std::make_unique<PreintegrateTask>();
  if (auto mn = n.get("method", true)) {
    p->method_pointer = mn->pointer();
    if (mn->expect_object({"propagator", "preintegrator"})) {
      if (mn->has("propagator") && mn->has("preintegrator")) {
        mn->fail(
            "give either \"propagator\" (preintegration by propagation) or \"preintegrator\" "
            "(native), not both");
      } else if (mn->has("propagator")) {
        if (auto s = ReadPluginId(*mn, "propagator", true, &p->method_pointer)) p->method_id = *s;
      } else if (mn->has("preintegrator")) {
        p->native = true;
        if (auto s = ReadPluginId(*mn, "preintegrator", true, &p->method_pointer))
          p->method_id = *s;
      } else {
        mn->checker().error(mn->child_pointer("propagator"),
                            "required key is missing (give \"propagator\" or \"preintegrator\")");
      }
    }
  }
  if (auto cn = n.get("conventions", false)) {
    p->conventions_pointer = cn->pointer();
    if (auto l = cn->distinct_string_list(true)) p->conventions = *l;
  }
  if (auto bn = n.get("bias", false))
    if (auto b = ReadBiasSpec(ctx, *bn)) p->bias = *b;
  if (auto iv = ReadIntervals(n, true)) p->keyframes = *iv;
  return p;
}

}  // namespace imuconv::pipeline
