// "optimize": `imuconv optimize` inside a pipeline. Every keyframe's state over the pipeline's
// IMU samples with its /ground_truth as the pose measurements and its /noise and /gravity
// (docs/optimize.md):
//   {"type": "optimize", "name": N, "keyframe_step": S, "method"?: ID, "convention"?: ID,
//    "residual"?: "gtsam"|"forster", "pose_sigma"?: [METRES, RADIANS],
//    "reintegrate_gyro"?: RAD_PER_S, "reintegrate_accel"?: M_PER_S2, "max_rounds"?: N,
//    "max_iterations"?: N}
// The task writes what `imuconv optimize --json` prints under its name and type.
//
// The solve is imuconv optimize's (apps/optimize, with Ceres), which links this library: it is
// registered from above (optimize_evaluator.h); here are only the grammar, the checks and the
// output.
#include <cmath>

#include "../spec/pipeline_spec.h"
#include "../spec/spec_data.h"
#include "context.h"
#include "imuconv/pipeline/optimize_evaluator.h"
#include "imuconv/printable.h"
#include "plugins_used.h"
#include "task.h"

namespace imuconv::pipeline {
namespace {

class OptimizeTask : public Task {
 public:
  OptimizeSettings settings;
  std::string method_pointer, convention_pointer;

  void plugins_used(PluginUse& use) const override {
    if (use.registry().has(PluginKind::Preintegrator, settings.method))
      use.add(PluginKind::Preintegrator, settings.method);
    else
      use.propagator(settings.method);
    use.add(PluginKind::StateConvention, settings.convention);
  }

  void check_plugins(RunContext& ctx, Checker& c) const override {
    if (!ctx.reg.has(PluginKind::Preintegrator, settings.method))
      ctx.check_id(c, PluginKind::Propagator, settings.method, method_pointer);
    ctx.check_id(c, PluginKind::StateConvention, settings.convention, convention_pointer);
  }

  void check_times(const RunContext& ctx, Checker& c) const override {
    if (!ctx.spec.has_noise)
      c.error("/noise", "required key is missing: task '" + Printable(name) + "' (" + pointer +
                            ", optimize) whitens its factors with it");
  }

  void run(RunContext& ctx, JsonWriter& w, TaskResult&) const override {
    const OptimizeEvaluator evaluate = GetOptimizeEvaluator();
    if (!evaluate)
      ctx.fail(pointer,
               "this program cannot run an optimize task: imuconv optimize (apps/optimize, built "
               "with Ceres) registers it, and it is not linked in");
    // Every sample and pose: the kept ranges are those of the tasks with intervals, and this
    // one solves over the whole sequence.
    std::optional<ImuData> whole_imu;
    if (ctx.imu_keep) whole_imu = ReadSpecImu(ctx.spec);
    std::optional<GroundTruth> whole_gt;
    if (ctx.gt_keep) {
      const GroundTruthSpec& g = *ctx.spec.gt;
      const ImuData& imu = whole_imu ? *whole_imu : ctx.imu;
      TimeOrigin o;
      if (imu.origin)
        o = *imu.origin;
      else
        o.unit = TimeUnit::s;
      ReadOptions ro;
      ro.timing = g.timing;
      whole_gt = g.format == "euroc" ? ReadEurocGroundTruth(g.path, o, ro)
                                     : ReadPoseGroundTruth(g.path, g.format, o, ro, g.sensor);
    }
    json out;
    try {
      out = evaluate(ctx.reg, whole_imu ? *whole_imu : ctx.imu, whole_gt ? *whole_gt : *ctx.gt,
                     ctx.spec.noise, ctx.spec.gravity, settings);
    } catch (const Error& e) {
      ctx.fail(pointer, e.what());
    }
    for (const auto& [key, value] : out.items()) {
      w.key(key);
      w.value(value);
    }
    const bool converged = out["solver"]["converged"].get<bool>();
    if (!converged && ctx.opt.unconverged_solves) ctx.opt.unconverged_solves->push_back(name);
    if (std::ostream* o = ctx.summary())
      *o << "optimize '" << name << "': " << out["keyframes"].size() << " keyframes, "
         << (converged ? "converged" : "DID NOT CONVERGE") << "\n";
  }
};

}  // namespace

std::unique_ptr<Task> ParseOptimize(const ParseContext& ctx, const Node& n) {
  n.expect_object({"type", "name", "description", "keyframe_step", "method", "convention",
                   "residual", "pose_sigma", "reintegrate_gyro", "reintegrate_accel", "max_rounds",
                   "max_iterations"});
  auto p = std::make_unique<OptimizeTask>();
  RequireImu(ctx, n, "optimize");
  if (!ctx.has_gt)
    n.checker().error(n.child_pointer("type"),
                      "an optimize task measures each keyframe's pose in the ground truth: add a "
                      "top-level /ground_truth source");
  OptimizeSettings& s = p->settings;
  if (auto step = n.number("keyframe_step", true)) {
    if (*step > 0 && std::isfinite(*step))
      s.keyframe_step = *step;
    else
      n.checker().error(n.child_pointer("keyframe_step"), "expected a duration > 0 (seconds)");
  }
  p->method_pointer = n.child_pointer("method");
  p->convention_pointer = n.child_pointer("convention");
  if (auto m = ReadPluginId(n, "method", false)) s.method = *m;
  if (auto c = ReadPluginId(n, "convention", false)) s.convention = *c;
  if (auto r = n.get("residual", false))
    if (auto kind = r->one_of({"gtsam", "forster"})) s.residual = *kind;
  if (auto ps = n.get("pose_sigma", false)) {
    if (auto v = ps->number_list(2)) {
      if (v->size() != 2 || !((*v)[0] >= kMinPoseSigma) || !((*v)[1] >= kMinPoseSigma))
        ps->fail(std::string("expected [METRES, RADIANS], two standard deviations >= ") +
                 kMinPoseSigmaText + " (optimize_evaluator.h: a smaller one overflows the cost)");
      else {
        s.pose_sigma_m = (*v)[0];
        s.pose_sigma_rad = (*v)[1];
      }
    }
  }
  for (const auto& [key, target] :
       {std::pair<const char*, double*>{"reintegrate_gyro", &s.reintegrate_gyro},
        {"reintegrate_accel", &s.reintegrate_accel}})
    if (auto v = n.number(key, false)) {
      if (*v > 0)
        *target = *v;
      else
        n.checker().error(n.child_pointer(key), "expected a threshold > 0");
    }
  if (auto rounds = n.integer("max_rounds", false)) {
    if (*rounds >= 1 && *rounds <= 100)
      s.max_rounds = static_cast<int>(*rounds);
    else
      n.checker().error(n.child_pointer("max_rounds"), "expected an integer in [1, 100]");
  }
  if (auto iterations = n.integer("max_iterations", false)) {
    if (*iterations >= 1 && *iterations <= 100000)
      s.max_iterations = static_cast<int>(*iterations);
    else
      n.checker().error(n.child_pointer("max_iterations"), "expected an integer in [1, 100000]");
  }
  return p;
}

}  // namespace imuconv::pipeline
