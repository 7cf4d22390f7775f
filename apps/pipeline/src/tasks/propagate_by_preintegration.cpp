// "propagate_by_preintegration": propagation by preintegration (paper section 3.2): the states,
// transition matrices and covariances from preintegrated measurements, chained (each step
// from the previous end) or each from its own start; compared with the ground truth where
// there is one. Unchained steps are independent: computed and written on the thread pool.
#include <cmath>
#include <cstdio>

#include "../forms/chart_matrix.h"
#include "../forms/increment.h"
#include "../forms/state.h"
#include "context.h"
#include "imuconv/printable.h"
#include "plugins_used.h"
#include "summary.h"
#include "task.h"

namespace imuconv::pipeline {
namespace {

// Chaining takes each step's start state from the previous step's end, so the measurements
// must tile time: step k starts where step k-1 ended. Within this tolerance: the one the
// measurement form uses for two statements of one time (forms/measurement.cpp,
// kTimeAgreement), so that a file that passes its own dt = t_end - t_start check chains; a
// gap that small moves the chained state by |v| x 1e-6 s, far below any IMU period, while the
// gaps, overlaps and repeats this refuses are whole intervals (0.06-0.44 m of error on
// EuRoC V1_01).
constexpr double kChainTolerance = 1e-6;

std::string Seconds(double t) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g s", t);
  return buf;
}

/// "measurement 3 (M.json: /measurements/3, [0.1 s, 0.2 s])": which, where, and when.
std::string DescribeMeasurement(const MeasurementsSpec& meas, const MeasRecord& r, std::size_t k) {
  std::string where =
      meas.task.empty() ? Printable(meas.file) + ": " + r.pointer : "task " + Quoted(meas.task);
  return "measurement " + std::to_string(k) + " (" + where + ", [" + Seconds(*r.t_s) + ", " +
         Seconds(*r.t_e) + "])";
}

/// Nothing if every measurement starts where the previous one ended (within
/// kChainTolerance); otherwise the sentence naming both. Measurements without t_start and
/// t_end cannot be checked and are chained in the order given.
std::optional<std::string> ChainBreak(const MeasurementsSpec& meas,
                                      const std::vector<MeasRecord>& ms) {
  for (std::size_t k = 1; k < ms.size(); ++k) {
    const MeasRecord& a = ms[k - 1];
    const MeasRecord& b = ms[k];
    if (!a.t_s || !a.t_e || !b.t_s || !b.t_e) continue;
    const double jump = *b.t_s - *a.t_e;
    if (std::abs(jump) <= kChainTolerance) continue;
    std::string what;
    if (std::abs(*b.t_s - *a.t_s) <= kChainTolerance &&
        std::abs(*b.t_e - *a.t_e) <= kChainTolerance)
      what = "repeats the interval of";
    else if (jump > 0.0)
      what = "leaves a gap of " + Seconds(jump) + " after";
    else if (*b.t_s < *a.t_s)
      what = "runs backwards (starts before the start of)";
    else
      what = "overlaps by " + Seconds(-jump) + ", so does not start at the end of";
    return "\"chain\": true needs each measurement to start where the previous one ended "
           "(tolerance 1e-6 s), but " +
           DescribeMeasurement(meas, b, k) + " " + what + " " +
           DescribeMeasurement(meas, a, k - 1) +
           "; give contiguous measurements, or set \"chain\": false to start each from its own "
           "state";
  }
  return std::nullopt;
}

class PropagateByPreintegrationTask : public Task {
 public:
  MeasurementsSpec meas;
  std::string convention = "left";
  StateSpec start;
  CovSpec cov;
  bool chain = false;
  bool has_chain_key =
      false;  // "chain" written (else chaining is the default of a given start state)
  std::optional<bool> compare_gt;

  const MeasurementsSpec* measurements() const override { return &meas; }

  KeptRecords kept_records(
      const std::function<std::size_t(const MeasurementsSpec&)>& count_of) const override {
    return {count_of(meas), sizeof(PropRecord), "step"};
  }

  void plugins_used(PluginUse& use) const override {
    use.state(convention);
    use.state_cov(cov);
    use.measurements();
  }

  /// A chain over a measurements file must tile time (ChainBreak), checked with the other
  /// times, before anything is integrated: otherwise it would integrate across a gap, or twice
  /// over an overlap, in silence.
  void check_times(const RunContext& ctx, Checker& c) const override {
    if (!chain || meas.file.empty()) return;
    if (const auto broken = ChainBreak(meas, ctx.measurements(meas)))
      c.error(pointer + (has_chain_key ? "/chain" : "/start"), *broken);
  }

  void check_plugins(RunContext& ctx, Checker& c) const override {
    ctx.check_id(c, PluginKind::StateConvention, convention, pointer + "/state_convention");
    if (ctx.reg.has(PluginKind::StateConvention, convention))
      ctx.check_cov_convention(c, cov, PluginKind::StateConvention, convention);
  }

  /// Step k from its start state (and covariance) to its end.
  void step(const RunContext& ctx, const std::vector<MeasRecord>& ms, std::size_t k,
            const ImuState& x_s, const Mat15& cov_s, PropRecord& pr,
            std::optional<GtComparison>& cmp) const {
    const MeasRecord& r = ms[k];
    const std::string where =
        meas.task.empty() ? r.pointer : meas.pointer + " (measurement " + std::to_string(k) + ")";
    const PropagationResult out =
        PropagateByPreintegration(ctx.reg, r.m, x_s, cov_s, convention, ctx.spec.gravity);
    if (compare_gt.value_or(r.t_e && ctx.gt_covers(*r.t_e))) {
      if (!r.t_e) ctx.fail(where, "comparing with ground truth needs t_end");
      cmp = ctx.compare_gt(out.x_e, *r.t_e, where);
    }
    pr = {x_s, out.x_e, out.Phi, out.cov, convention, r.t_s, r.t_e};
  }

  /// The start of step k when it does not continue the previous one: given, or the ground
  /// truth at its start.
  ImuState start_state(const RunContext& ctx, const std::vector<MeasRecord>& ms,
                       std::size_t k) const {
    if (!start.ground_truth) return start.x;
    const MeasRecord& r = ms[k];
    if (!r.t_s)
      ctx.fail(start.pointer, "starting from ground truth needs t_start of " +
                                  MeasurementsName(meas) + " measurement " + std::to_string(k));
    return ctx.gt_at(*r.t_s, start.pointer);
  }

  void write_step(const RunContext& ctx, JsonWriter& w, const MeasRecord& r, std::size_t k,
                  const PropRecord& pr, const std::optional<GtComparison>& cmp) const {
    const auto& blocks = ctx.blocks(PluginKind::StateConvention, convention);
    w.begin_object();
    w.key("index");
    w.unsigned_integer(k);
    ctx.write_times(w, r.t_s, r.t_e);
    w.key("dt");
    w.number(r.m.dt);
    w.key("x_s");
    WriteState(w, pr.x_s);
    w.key("x_e");
    WriteState(w, pr.x_e);
    if (!ctx.spec.omit.Phi) {
      w.key("Phi");
      WriteChart(w, pr.Phi, convention, blocks);
    }
    if (!ctx.spec.omit.cov) {
      w.key("cov");
      WriteCovariance(w, pr.cov, convention, blocks);
    }
    if (cmp) {
      w.key("ground_truth");
      WriteComparison(w, *cmp);
    }
    w.end_object();
  }

  void run(RunContext& ctx, JsonWriter& w, TaskResult& res) const override {
    const auto& ms = ctx.measurements(meas);
    const std::size_t n = ms.size();
    const bool keep = ctx.kept(name);
    if (keep) res.props.resize(n);
    std::ostream* o = ctx.summary();
    if (o) {
      *o << "\npropagate_by_preintegration '" << name << "': " << MeasurementsName(meas)
         << ", state convention " << convention << ", "
         << (start.ground_truth ? (chain ? "chained from the ground truth at the first keyframe"
                                         : "each interval from the ground truth at its start")
                                : (chain ? "chained from the given start state"
                                         : "each interval from the given start state"))
         << "\n";
    }
    StepTable table(o, ctx.gt && compare_gt.value_or(true), n, ctx.opt.every_row);
    const auto row = [&](std::size_t k, const ImuState& x_e,
                         const std::optional<GtComparison>& cmp) {
      const MeasRecord& r = ms[k];
      table.row(k, r.t_s, r.m.dt, r.m.delta.dp.norm(), RotationAngleDeg(r.m.delta.dR),
                cmp ? &cmp->e : nullptr);
      if (ctx.opt.on_step) {
        std::optional<std::int64_t> abs_ns;
        if (r.t_e && ctx.imu.origin) abs_ns = ctx.imu.origin->absolute_ns(*r.t_e);
        StepOut s{name, k, r.t_e, abs_ns, x_e, std::nullopt, std::nullopt, std::nullopt};
        if (cmp) {
          s.position_error_m = cmp->e.pos;
          s.rotation_error_deg = cmp->e.rot;
          s.velocity_error_mps = cmp->e.vel;
        }
        ctx.opt.on_step(s);
      }
    };
    WriteMeasurementsSource(w, meas);
    w.key("state_convention");
    w.string(convention);
    w.key("start");
    if (start.ground_truth)
      w.string("ground_truth");
    else
      WriteState(w, start.x);
    w.key("chain");
    w.boolean(chain);
    w.key("steps");
    w.begin_array();
    if (chain) {
      // A preintegrate task's intervals are consecutive keyframes: they tile time by
      // construction. A file's were checked by check_times.
      // One after the other (each starts at the previous end), written straight into w: the
      // text write_elements would splice. Only the previous step is held.
      PropRecord prev;
      for (std::size_t k = 0; k < n; ++k) {
        PropRecord pr;
        std::optional<GtComparison> cmp;
        if (k == 0) {
          const ImuState x = start_state(ctx, ms, 0);
          step(ctx, ms, 0, x, ctx.start_cov(cov, convention, x), pr, cmp);
        } else {
          step(ctx, ms, k, prev.x_e, prev.cov, pr, cmp);
        }
        write_step(ctx, w, ms[k], k, pr, cmp);
        ctx.out.count_record();
        row(k, pr.x_e, cmp);
        if (keep) res.props[k] = pr;
        prev = std::move(pr);
        ctx.out.flush(false);
      }
    } else {
      const std::size_t window = ctx.out.window();
      std::vector<std::optional<GtComparison>> cmps(std::min(window, n));
      std::vector<ImuState> ends(
          std::min(window, n));  // each step's prediction, until its row is printed
      ctx.out.write_elements(
          w, n,
          [&](JsonWriter& sw, std::size_t k) {
            PropRecord local;
            PropRecord& pr = keep ? res.props[k] : local;
            std::optional<GtComparison>& cmp = cmps[k % window];
            cmp.reset();
            const ImuState x = start_state(ctx, ms, k);
            step(ctx, ms, k, x, ctx.start_cov(cov, convention, x), pr, cmp);
            ends[k % window] = pr.x_e;
            write_step(ctx, sw, ms[k], k, pr, cmp);
          },
          [&](std::size_t k) { row(k, ends[k % window], cmps[k % window]); });
    }
    w.end_array();
    table.write_ground_truth_summary(w);
    table.print_totals(n);
  }
};

}  // namespace

std::unique_ptr<Task> ParsePropagateByPreintegration(const ParseContext& ctx, const Node& n) {
  n.expect_object({"type", "name", "description", "measurements", "state_convention", "start",
                   "chain", "compare_ground_truth"});
  auto p = NewMeasurementsTask<PropagateByPreintegrationTask>(ctx, n);
  if (auto s = ReadPluginId(n, "state_convention", false)) p->convention = *s;
  ReadStart(ctx, n, p->start, p->cov);
  p->chain = !p->start.ground_truth;
  if (auto b = n.boolean("chain", false)) {
    p->chain = *b;
    p->has_chain_key = true;
  }
  p->compare_gt = ReadCompareGroundTruth(ctx, n);
  return p;
}

}  // namespace imuconv::pipeline
