// "propagate": one propagator run over one interval from a given (or ground-truth) start
// state and covariance, in a state convention; compared with the ground truth when there is
// one at the end.
#include "../forms/chart_matrix.h"
#include "../forms/comparison.h"
#include "../forms/state.h"
#include "../io/message_text.h"
#include "context.h"
#include "plugins_used.h"
#include "task.h"

namespace imuconv::pipeline {
namespace {

class PropagateTask : public Task {
 public:
  std::string propagator, convention = "left";
  StateSpec start;
  CovSpec cov;
  IntervalsSpec interval;
  std::optional<bool> compare_gt;

  const IntervalsSpec* intervals() const override { return &interval; }

  KeptRecords kept_records(
      const std::function<std::size_t(const MeasurementsSpec&)>&) const override {
    return {1, sizeof(PropRecord), "propagation"};
  }

  void plugins_used(PluginUse& use) const override {
    use.propagator(propagator);
    use.state(convention);
    use.state_cov(cov);
  }

  void check_plugins(RunContext& ctx, Checker& c) const override {
    ctx.check_id(c, PluginKind::Propagator, propagator, pointer + "/propagator");
    ctx.check_id(c, PluginKind::StateConvention, convention, pointer + "/state_convention");
    if (ctx.reg.has(PluginKind::StateConvention, convention))
      ctx.check_cov_convention(c, cov, PluginKind::StateConvention, convention);
  }

  void check_times(const RunContext& ctx, Checker& c) const override {
    if (compare_gt.value_or(false) && interval.size())
      ctx.check_gt(c, interval.back(), interval.pointer_of(interval.size() - 1));
    if (interval.size() < 2 || !ctx.have_imu) return;  // (no /imu is reported by the parser)
    ctx.check_interval_times(c, interval);
    if (start.ground_truth) ctx.check_gt_state(c, interval.front(), start.pointer);
  }

  void run(RunContext& ctx, JsonWriter& w, TaskResult& res) const override {
    const double ts = interval.front(), te = interval.back();
    PropagationInput in;
    in.x_s = start.ground_truth ? ctx.gt_at(ts, start.pointer) : start.x;
    in.cov_s = ctx.start_cov(cov, convention, in.x_s);
    in.noise = ctx.spec.noise;
    in.gravity = ctx.spec.gravity;
    in.window = ctx.window(ts, te);
    const PropagationResult r = ctx.reg.propagate(propagator, convention, in);
    std::optional<GtComparison> cmp;
    if (compare_gt.value_or(ctx.gt_covers(te)))
      cmp = ctx.compare_gt(r.x_e, te, pointer + "/interval/t_end");
    const OmitSpec& omit = ctx.spec.omit;
    const auto& blocks = ctx.blocks(PluginKind::StateConvention, convention);
    w.key("propagator");
    w.string(propagator);
    w.key("state_convention");
    w.string(convention);
    w.key("interval");
    w.begin_object();
    ctx.write_times(w, ts, te);
    w.end_object();
    w.key("n_knots");
    w.unsigned_integer(in.window.size());
    w.key("x_s");
    WriteState(w, in.x_s);
    if (!omit.cov) {
      w.key("cov_s");
      WriteCovariance(w, in.cov_s, convention, blocks);
    }
    w.key("x_e");
    WriteState(w, r.x_e);
    if (!omit.Phi) {
      w.key("Phi");
      WriteChart(w, r.Phi, convention, blocks);
    }
    if (!omit.cov) {
      w.key("cov");
      WriteCovariance(w, r.cov, convention, blocks);
    }
    if (cmp) {
      w.key("ground_truth");
      WriteComparison(w, *cmp);
    }
    ctx.out.count_record();
    res.props.push_back({in.x_s, r.x_e, r.Phi, r.cov, convention, ts, te});
    if (std::ostream* o = ctx.summary()) {
      *o << "propagate '" << name << "': " << propagator << " over [" << Num(ts) << ", " << Num(te)
         << "] s (" << in.window.size() << " knots), state convention " << convention;
      if (cmp)
        *o << "; vs ground truth: position " << Num(cmp->e.pos, 4) << " m, rotation "
           << Num(cmp->e.rot, 4) << " deg";
      *o << "\n";
    }
  }
};

}  // namespace

std::unique_ptr<Task> ParsePropagate(const ParseContext& ctx, const Node& n) {
  n.expect_object({"type", "name", "description", "propagator", "state_convention", "start",
                   "interval", "compare_ground_truth"});
  RequireImu(ctx, n, "propagate");
  auto p = std::make_unique<PropagateTask>();
  if (auto s = ReadPluginId(n, "propagator", true)) p->propagator = *s;
  if (auto s = ReadPluginId(n, "state_convention", false)) p->convention = *s;
  ReadStart(ctx, n, p->start, p->cov);
  if (auto iv = ReadIntervals(n, false)) p->interval = *iv;
  p->compare_gt = ReadCompareGroundTruth(ctx, n);
  return p;
}

}  // namespace imuconv::pipeline
