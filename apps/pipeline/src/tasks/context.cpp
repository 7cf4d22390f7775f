#include "context.h"

#include "imuconv/pipeline/interval_samples.h"
#include "imuconv/pipeline/timing.h"
#include "imuconv/window.h"

#include "../forms/input_checks.h"
#include "../io/message_text.h"
#include "imuconv/printable.h"
#include "task.h"

namespace imuconv::pipeline {

RunContext::RunContext(const PipelineSpec& s, const Registry& r, const RunOptions& o,
                       Output& output)
    : spec(s), reg(r), opt(o), out(output) {
  for (const auto& t : spec.tasks) by_name_.emplace(t->name, t.get());
}

void RunContext::fail(const std::string& pointer, const std::string& message) const {
  throw TaskFailure(spec.file + ": " + pointer + ": " + message);
}

const std::string& RunContext::type_of(const std::string& name) const {
  static const std::string kNone = "?";
  const auto it = by_name_.find(name);
  return it == by_name_.end() ? kNone : it->second->type;
}

SampleWindow RunContext::window(double ts, double te) const {
  SampleWindow w;
  const Status st = MakeWindow(imu.samples.data(), imu.samples.size(), ts, te, w);
  if (!st.ok()) throw Error(st.message());
  return w;
}

/// Where the ground truth ends, for a time it does not cover. Only the rows around the
/// times the tasks use are read, but every such time is in that range: a time before the
/// first row read is before the file's first row (and after the last, after its last).
std::string RunContext::gt_uncovered(double t) const {
  return "ground truth does not cover t = " + Num(t, 10) + " s (" + Printable(gt->source) +
         (t < gt->t.front() ? " starts at t = " + Num(gt->t.front(), 10)
                            : " ends at t = " + Num(gt->t.back(), 10)) +
         " s)";
}

namespace {
std::string PoseOnly(const GroundTruth& gt) {
  return "the ground truth (" + Printable(gt.source) + ", format \"" + gt.format +
         "\") has poses only: a start state or bias estimate from it would need velocity and "
         "biases; give them "
         "in the task instead";
}
}  // namespace

ImuState RunContext::gt_at(double t, const std::string& pointer) const {
  if (!gt) fail(pointer, "there is no /ground_truth");
  if (!gt->full_state) fail(pointer, PoseOnly(*gt));
  auto x = gt->at(t);
  if (!x) fail(pointer, gt_uncovered(t));
  return *x;
}

GtComparison RunContext::compare_gt(const ImuState& predicted, double t,
                                    const std::string& pointer) const {
  if (!gt) fail(pointer, "there is no /ground_truth");
  auto x = gt->at(t);
  if (!x) fail(pointer, gt_uncovered(t));
  return Compare(predicted, *x, gt->full_state);
}

const std::vector<MeasRecord>& RunContext::measurements(const MeasurementsSpec& m) const {
  if (!m.task.empty()) return results.at(m.task).meas;
  return files.at(m.file);
}

std::vector<std::size_t> RunContext::select(const std::vector<MeasRecord>& ms,
                                            const std::optional<std::size_t>& index,
                                            const std::string& task_pointer,
                                            const std::string& what) const {
  if (!index) {
    std::vector<std::size_t> all(ms.size());
    for (std::size_t i = 0; i < ms.size(); ++i) all[i] = i;
    return all;
  }
  if (*index >= ms.size())
    fail(task_pointer + "/index", what + " has " + std::to_string(ms.size()) +
                                      " measurement(s); index " + std::to_string(*index) +
                                      " is out of range");
  return {*index};
}

Mat15 RunContext::start_cov(const CovSpec& cov, const std::string& conv, const ImuState& x) const {
  if (!cov.given) return Mat15::Zero();
  if (cov.m().convention && *cov.m().convention != conv)
    return reg.convert_covariance(*cov.m().convention, conv, x, cov.m().m);
  return cov.m().m;
}

void RunContext::write_times(JsonWriter& w, std::optional<double> ts,
                             std::optional<double> te) const {
  WriteTimes(w, ts, te, imu.origin);
}

void RunContext::check_id(Checker& c, PluginKind kind, const std::string& id,
                          const std::string& pointer) const {
  CheckPluginId(c, reg, kind, id, pointer);
}

void RunContext::check_cov_convention(Checker& c, const CovSpec& cov, PluginKind kind,
                                      const std::string& target) const {
  if (!cov.given) return;
  const std::string conv = cov.m().convention.value_or(target);
  if (cov.m().convention) {
    check_id(c, kind, conv, cov.m().pointer + "/convention");
    if (!reg.has(kind, conv)) return;
  }
  if (cov.m().blocks && reg.has(kind, conv)) {
    const auto& expect = blocks(kind, conv);
    if (*cov.m().blocks != expect)
      c.error(cov.m().pointer + "/blocks", "blocks [" + Join(*cov.m().blocks) +
                                               "] do not match the block order of '" + conv +
                                               "': [" + Join(expect) + "]");
  }
}

void RunContext::check_time(Checker& c, double t, const std::string& pointer) const {
  const double t0 = imu.samples.front().t, t1 = imu.samples.back().t;
  if (t < t0)
    c.error(pointer, "t = " + Num(t, 10) + " s is before the first IMU sample (t = " + Num(t0, 10) +
                         " s; times are relative to the time origin)");
  else if (t > t1)
    c.error(pointer, "t = " + Num(t, 10) + " s is after the last IMU sample (t = " + Num(t1, 10) +
                         " s; times are relative to the time origin)");
}

void RunContext::check_gt(Checker& c, double t, const std::string& pointer) const {
  if (!gt) return;
  if (!(t >= gt->t.front() && t <= gt->t.back())) c.error(pointer, gt_uncovered(t));
}

void RunContext::check_gt_state(Checker& c, double t, const std::string& pointer) const {
  if (!gt) return;
  if (!gt->full_state)
    c.error(pointer, PoseOnly(*gt));
  else
    check_gt(c, t, pointer);
}

void RunContext::check_intervals_hold_samples(Checker& c, const IntervalsSpec& iv) const {
  if (spec.allow_empty_intervals) return;
  const auto empty = FindEmptyInterval(
      imu.samples, iv.size(), [&iv](std::size_t k) { return iv.time(k); }, IntervalEnds::kIncluded);
  if (!empty) return;
  const bool generated = iv.form == IntervalsSpec::Form::Generated;
  c.error(generated ? iv.pointer + "/step" : iv.pointer_of(empty->index + 1),
          EmptyIntervalSentence(*empty, IntervalEnds::kIncluded,
                                generated ? std::optional<double>(iv.step) : std::nullopt,
                                iv.size() - 1) +
              ". Set \"allow_empty_intervals\": true at the top of the pipeline if that is meant");
}

void RunContext::check_interval_times(Checker& c, const IntervalsSpec& iv) const {
  check_intervals_hold_samples(c, iv);
  // Generated keyframes increase, so the first one and the first one past the data say all
  // there is (one message, not one per keyframe).
  if (iv.form != IntervalsSpec::Form::Generated) {
    for (std::size_t i = 0; i < iv.size(); ++i) check_time(c, iv.time(i), iv.pointer_of(i));
    return;
  }
  check_time(c, iv.front(), iv.pointer_of(0));
  const double t1 = imu.samples.back().t;
  if (!(iv.back() > t1)) return;
  std::size_t lo = 0, hi = iv.size() - 1;  // the first keyframe after t1 is in (lo, hi]
  while (hi - lo > 1) {
    const std::size_t mid = lo + (hi - lo) / 2;
    (iv.time(mid) > t1 ? hi : lo) = mid;
  }
  if (iv.time(lo) > t1) hi = lo;
  c.error(iv.pointer_of(iv.size() - 1),
          "t = " + Num(iv.time(hi), 10) + " s is after the last IMU sample (t = " + Num(t1, 10) +
              " s; times are relative to the time origin): keyframe " + std::to_string(hi) +
              " of " + std::to_string(iv.size()) +
              (hi + 1 < iv.size() ? " and every later one up to end" : std::string()));
}

}  // namespace imuconv::pipeline
