// "check": `imuconv check` inside a pipeline. A measurements file whose charts may be
// undeclared ("unknown") is compared with preintegration by propagation over the pipeline's
// IMU samples, with the pipeline's noise (docs/check.md):
//   {"type": "check", "name": N, "measurements": {"file": PATH}}
// Its times are on the pipeline's time axis, as every measurements file of a pipeline. The
// task writes what `imuconv check --json` prints (verdict, tolerances, measurements) under
// its name and type, after "measurements_file"; an inconsistent verdict is reported to
// RunOptions::inconsistent_checks (imuconv run then exits 1, the document written;
// docs/exit-codes.md).
//
// The evaluation itself is imuconv check's (apps/check), which links this library: it is
// registered from above (check_evaluator.h, SetCheckEvaluator); here are only the grammar, the
// checks of the input and the output.
#include <algorithm>

#include "../io/message_text.h"
#include "../spec/spec_data.h"
#include "context.h"
#include "imuconv/pipeline/check_evaluator.h"
#include "imuconv/printable.h"
#include "plugins_used.h"
#include "task.h"

namespace imuconv::pipeline {
namespace {

class CheckTask : public Task {
 public:
  std::string file;  // resolved
  std::string file_pointer;

  const std::string* input_file() const override { return file.empty() ? nullptr : &file; }

  void plugins_used(PluginUse& use) const override {
    // What check compares with (apps/check/references.h, imuconv/check/candidates.h): the three
    // propagator schemes, every registered preintegrator, and the numbers in every increment
    // convention.
    for (const char* id : {"euler", "midpoint", "rk4"}) use.propagator(id);
    for (const auto& id : use.registry().ids(PluginKind::Preintegrator))
      use.add(PluginKind::Preintegrator, id);
    for (const auto& id : use.registry().ids(PluginKind::IncrementConvention)) use.increment(id);
    use.measurements();
  }

  void check_plugins(RunContext&, Checker&) const override {}

  /// The measurements are read here, once the data's time origin is known (their times are
  /// put on the pipeline's axis); their charts are checked against the registry by the reader.
  void check_times(const RunContext& ctx, Checker& c) const override {
    if (!ctx.spec.has_noise) {
      c.error("/noise", "required key is missing: task '" + Printable(name) + "' (" + pointer +
                            ", check) integrates IMU samples with it");
      return;
    }
    if (!ctx.have_imu) return;  // reported when parsed
    declared_ = ReadDeclaredMeasurementFile(file, ctx.reg, ctx.origin_ns);
    // Every interval inside the IMU data (as every interval of a pipeline): the check would
    // otherwise extrapolate. The whole data is at hand unless another task's range was kept.
    const ImuData* data = &ctx.imu;
    if (ctx.imu_keep) {
      whole_ = ReadSpecImu(ctx.spec);
      data = &*whole_;
    }
    const double t0 = data->samples.front().t, t1 = data->samples.back().t;
    std::vector<Issue> issues;
    for (const DeclaredMeasurement& m : declared_) {
      if (!m.t_s || !m.t_e)
        issues.push_back(
            {m.pointer,
             "t_start and t_end (seconds on the pipeline's time axis) are needed to check a "
             "measurement"});
      // 1e-6 s: the measurements form's own agreement of two statements of one time.
      else if (*m.t_s < t0 - 1e-6 || *m.t_e > t1 + 1e-6)
        issues.push_back({m.pointer, "the interval [" + Num(*m.t_s, 12) + ", " + Num(*m.t_e, 12) +
                                         "] s is not inside the IMU samples [" + Num(t0, 12) +
                                         ", " + Num(t1, 12) +
                                         "] s (times relative to the pipeline's time origin)"});
    }
    if (!issues.empty()) throw ConfigError(file, issues);
  }

  void run(RunContext& ctx, JsonWriter& w, TaskResult&) const override {
    const CheckEvaluator evaluate = GetCheckEvaluator();
    if (!evaluate)
      ctx.fail(pointer,
               "this program cannot run a check task: imuconv check (apps/check) registers it, and "
               "it is "
               "not linked in; run the pipeline with the imuconv command");
    const ImuData& data = whole_ ? *whole_ : ctx.imu;
    const CheckEvaluation e = evaluate(ctx.reg, data.samples, ctx.spec.noise, declared_, file);
    w.key("measurements_file");
    w.string(file);
    for (const char* key : {"verdict", "tolerances", "measurements"}) {
      w.key(key);
      w.value(e.report.at(key));
    }
    if (!e.consistent && ctx.opt.inconsistent_checks) ctx.opt.inconsistent_checks->push_back(name);
    if (std::ostream* o = ctx.summary())
      *o << "check '" << name << "': " << declared_.size() << " measurement(s) of " << file << ": "
         << (e.consistent ? "consistent" : "INCONSISTENT") << "\n";
  }

 private:
  // Filled by check_times, used by run (the stages run once, in order, on one thread).
  mutable std::vector<DeclaredMeasurement> declared_;
  mutable std::optional<ImuData> whole_;
};

}  // namespace

std::unique_ptr<Task> ParseCheck(const ParseContext& ctx, const Node& n) {
  n.expect_object({"type", "name", "description", "measurements"});
  auto p = std::make_unique<CheckTask>();
  RequireImu(ctx, n, "check");
  if (auto m = n.get("measurements", true)) {
    p->file_pointer = m->pointer();
    if (m->is_object()) {
      if (m->expect_object({"file"}))
        if (auto f = m->string("file", true)) p->file = ctx.resolve(*f);
    } else {
      m->fail(
          "expected {\"file\": PATH}: a check reads a measurements file "
          "(schemas/measurements.schema.json), "
          "found " +
          TypeName(m->value()));
    }
  }
  return p;
}

}  // namespace imuconv::pipeline
