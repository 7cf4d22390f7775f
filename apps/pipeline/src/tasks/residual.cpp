// "residual": the residual of a measurement between two states (GTSAM's ImuFactor or
// Forster's), with its Jacobians, covariance and squared Mahalanobis distance.
#include <Eigen/Cholesky>

#include "../context.h"
#include "../forms/chart_matrix.h"
#include "../forms/state.h"
#include "../plugins_used.h"
#include "../run_util.h"
#include "task.h"

namespace imuconv::pipeline {
namespace {

class ResidualTask : public Task {
 public:
  ResidualKind kind = ResidualKind::Gtsam;
  std::string kind_name;
  MeasurementsSpec meas;
  std::string convention = "left";
  StateSpec start, end;
  std::optional<std::size_t> index;

  const MeasurementsSpec* measurements() const override { return &meas; }

  void plugins_used(PluginUse& use) const override {
    use.state(convention);
    use.measurements();
  }

  void check_plugins(RunContext& ctx, Checker& c) const override {
    ctx.check_id(c, PluginKind::StateConvention, convention, pointer + "/state_convention");
  }

  ImuState state_at(const RunContext& ctx, const StateSpec& s, std::optional<double> t, const char* which) const {
    if (!s.ground_truth) return s.x;
    if (!t) ctx.fail(s.pointer, std::string("ground truth needs the measurement's ") + which + " time");
    return ctx.gt_at(*t, s.pointer);
  }

  void run(RunContext& ctx, JsonWriter& w, TaskResult&) const override {
    const auto& ms = ctx.measurements(meas);
    const auto sel = ctx.select(ms, index, pointer, MeasurementsName(meas));
    if ((!start.ground_truth || !end.ground_truth) && sel.size() > 1)
      ctx.fail(pointer, "explicit start/end states go with one measurement; give \"index\" (" + MeasurementsName(meas) +
                            " has " + std::to_string(ms.size()) + ")");
    static const std::vector<std::string> rblocks = {"theta", "p", "v", "bg", "ba"};
    const std::string rconv = "residual_" + kind_name;
    const auto& sb = ctx.blocks(PluginKind::StateConvention, convention);
    const auto& ib = ctx.blocks(PluginKind::IncrementConvention, "preint_reference");
    w.key("kind");
    w.string(kind_name);
    WriteMeasurementsSource(w, meas);
    w.key("state_convention");
    w.string(convention);
    w.key("residuals");
    w.begin_array();
    double sum_m2 = 0;
    std::size_t n_m2 = 0;
    for (std::size_t k : sel) {
      const MeasRecord& r = ms[k];
      const ImuState xs = state_at(ctx, start, r.t_s, "start"), xe = state_at(ctx, end, r.t_e, "end");
      const Residual res = ComputeResidual(ctx.reg, kind, r.m, xs, xe, convention, ctx.spec.gravity);
      w.begin_object();
      w.key("index");
      w.unsigned_integer(k);
      ctx.write_times(w, r.t_s, r.t_e);
      w.key("x_s");
      WriteState(w, xs);
      w.key("x_e");
      WriteState(w, xe);
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
      const Eigen::LDLT<Mat15> ldlt(res.cov);
      if (ldlt.info() == Eigen::Success && ldlt.isPositive() && ldlt.vectorD().minCoeff() > 0.0) {
        const double m2 = res.r.dot(ldlt.solve(res.r));
        w.key("mahalanobis_squared");
        w.number(m2);
        sum_m2 += m2;
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
      if (n_m2) *o << ", mean r^T cov^-1 r = " << Num(sum_m2 / static_cast<double>(n_m2), 4) << " (15 dof)";
      *o << "\n";
    }
  }
};

}  // namespace

std::unique_ptr<Task> ParseResidual(const ParseContext& ctx, const Node& n) {
  n.expect_object({"type", "name", "description", "kind", "measurements", "state_convention", "start", "end", "index"});
  auto p = std::make_unique<ResidualTask>();
  if (auto kn = n.get("kind", true))
    if (auto k = kn->one_of({"gtsam", "forster"})) {
      p->kind_name = *k;
      p->kind = *k == "gtsam" ? ResidualKind::Gtsam : ResidualKind::Forster;
    }
  if (auto m = ReadMeasurementsSpec(ctx, n)) p->meas = *m;
  if (auto s = ReadPluginId(n, "state_convention", false)) p->convention = *s;
  p->index = ReadIndex(n);
  for (auto [key, dst] : {std::pair<const char*, StateSpec*>{"start", &p->start}, {"end", &p->end}}) {
    if (auto sn = n.get(key, false)) {
      if (auto s = ReadStateSpec(ctx, *sn)) *dst = *s;
    } else if (ctx.has_gt) {
      dst->ground_truth = true;
      dst->pointer = n.child_pointer(key);
    } else {
      n.checker().error(n.child_pointer(key), "required key is missing (there is no /ground_truth to default to)");
    }
  }
  return p;
}

}  // namespace imuconv::pipeline
