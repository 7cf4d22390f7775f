// Running a parsed pipeline, in stages: check ids (plugin ids and charts against the
// registry), load data (only the time ranges the tasks use), check times (against the data),
// then execute and stream (each task writes its part of the output document as it runs).
// The stages know no task kind: they ask each task (tasks/task.h).
#include <algorithm>
#include <cstdint>
#include <optional>
#include <ostream>
#include <tuple>
#include <unordered_map>

#include "../io/output.h"
#include "../io/result_collector.h"
#include "../spec/pipeline_spec.h"
#include "../spec/spec_data.h"
#include "../tasks/context.h"
#include "../tasks/plugins_used.h"
#include "../tasks/results.h"
#include "../tasks/task.h"
#include "imuconv/kernels/preintegration.h"
#include "imuconv/pipeline/file_digest.h"
#include "imuconv/pipeline/imu_plausibility.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/result_arrays.h"
#include "imuconv/printable.h"

#ifndef IMUCONV_VERSION
#define IMUCONV_VERSION "unknown"
#endif

namespace imuconv::pipeline {
namespace {

using TimeRange = std::optional<std::pair<double, double>>;

void Extend(TimeRange& r, double a, double b) {
  r = r ? std::make_pair(std::min(r->first, a), std::max(r->second, b)) : std::make_pair(a, b);
}

/// Stage "check ids".
void CheckRegistry(RunContext& ctx) {
  Checker c(ctx.spec.file);
  for (const auto& t : ctx.spec.tasks) t->check_plugins(ctx, c);
  c.throw_if_errors();
}

/// Stage "load data". Only the samples the tasks integrate over are kept (the readers still
/// check every line and keep one sample beyond each end, for interpolation).
void LoadData(RunContext& ctx) {
  const PipelineSpec& s = ctx.spec;
  TimeRange imu_range;
  for (const auto& t : s.tasks)
    if (const IntervalsSpec* iv = t->intervals()) Extend(imu_range, iv->front(), iv->back());
  if (s.imu) {
    ReadOptions ro;
    ro.timing = s.imu->timing;
    ro.keep = imu_range;
    if (s.imu->format == ImuSourceSpec::Format::Euroc) {
      ctx.imu = ReadEurocImu(s.imu->path, s.imu->origin_ns, ro);
      ctx.imu_keep = imu_range;
    } else if (s.imu->format == ImuSourceSpec::Format::Csv) {
      ctx.imu = ReadCsvImu(s.imu->path, s.imu->csv, ro);
      ctx.imu_keep = imu_range;
    } else {
      ctx.imu = InlineImu(s);
    }
    ctx.have_imu = true;
    if (ctx.imu.origin) ctx.origin_ns = ctx.imu.origin->nanoseconds();
    // With a kept range, fewer than 2 samples means the range misses the data: the time
    // checks say which time is outside.
    if (ctx.imu.samples.size() < 2 && !(ctx.imu_keep && !ctx.imu.samples.empty()))
      throw ReadError(ctx.imu.source, 0,
                      "has " + std::to_string(ctx.imu.samples.size()) +
                          " IMU sample(s); at least 2 are needed");
  }
  // Measurement files (on the IMU data's time axis, so after it).
  for (const auto& t : s.tasks)
    if (const MeasurementsSpec* m = t->measurements();
        m && !m->file.empty() && !ctx.files.count(m->file))
      ctx.files[m->file] = ReadMeasurementFile(m->file, ctx.reg, ctx.origin_ns);
  if (s.gt) {
    TimeOrigin o;
    if (ctx.imu.origin)
      o = *ctx.imu.origin;
    else
      o.unit = TimeUnit::s;  // inline samples without an origin: GT stamps taken as absolute
    // Ground truth is looked up at interval ends and at the measurements' times.
    TimeRange range = imu_range;
    for (const auto& [file, records] : ctx.files)
      for (const auto& r : records)
        for (const auto& tm : {r.t_s, r.t_e})
          if (tm) Extend(range, *tm, *tm);
    ReadOptions ro;
    ro.timing = s.gt->timing;
    ro.keep = range;
    ctx.gt = s.gt->format == "euroc"
                 ? ReadEurocGroundTruth(s.gt->path, o, ro)
                 : ReadPoseGroundTruth(s.gt->path, s.gt->format, o, ro, s.gt->sensor);
    ctx.gt_keep = range;
  }
  CheckImuAgainstKnownData(s, ctx.imu, ctx.gt ? &*ctx.gt : nullptr);
}

/// Stage "check times".
void CheckTimes(const RunContext& ctx) {
  Checker c(ctx.spec.file);
  for (const auto& t : ctx.spec.tasks) t->check_times(ctx, c);
  c.throw_if_errors();
}

void WriteKept(JsonWriter& w, const TimeRange& keep) {
  if (!keep) return;
  w.key("kept_range");
  w.begin_line_array();
  w.number(keep->first);
  w.number(keep->second);
  w.end_array();
}

/// {"source", COUNT_KEY, "t_first", "t_last", "kept_range"?} of a data source.
void WriteSource(JsonWriter& w, const char* key, const std::string& source, const char* count_key,
                 std::size_t count, double t_first, double t_last, const TimeRange& keep) {
  w.key(key);
  w.begin_object();
  w.key("source");
  w.string(source);
  w.key(count_key);
  w.unsigned_integer(count);
  w.key("t_first");
  w.number(t_first);
  w.key("t_last");
  w.number(t_last);
  WriteKept(w, keep);
  w.end_object();
}

/// The document's keys before "tasks".
void WriteHead(const RunContext& ctx, JsonWriter& w) {
  const PipelineSpec& s = ctx.spec;
  w.key("imuconv_version");
  w.string(IMUCONV_VERSION);
  w.key("pipeline");
  w.string(s.file);
  if (!s.description.empty()) {
    w.key("description");
    w.string(s.description);
  }
  if (ctx.origin_ns) {
    w.key("time_origin_ns");
    w.integer(*ctx.origin_ns);
  }
  w.key("times");
  w.string(ctx.origin_ns ? "seconds relative to time_origin_ns; *_abs_ns are absolute nanoseconds"
                         : "seconds, as given");
  w.key("gravity");
  w.vector(s.gravity);
  if (s.has_noise) {
    w.key("noise");
    w.value(NoiseToJson(s.noise));
  }
  // Provenance: which file (and version) each plugin the tasks used came from, so that a
  // plugin overriding another's id is visible in the output.
  w.key("plugins");
  w.begin_array();
  for (const PluginInfo* info : PluginsUsed(s, ctx.reg, ctx.files)) {
    w.begin_object();
    w.key("id");
    w.string(info->id);
    w.key("kind");
    w.string(KindName(info->kind));
    w.key("file");
    w.string(info->file);
    w.key("version");
    w.string(info->version);
    w.end_object();
  }
  w.end_array();
  // Only the part of the data the tasks need is read into memory: say which.
  if (ctx.have_imu)
    WriteSource(w, "imu", ctx.imu.source, "samples", ctx.imu.samples.size(),
                ctx.imu.samples.front().t, ctx.imu.samples.back().t, ctx.imu_keep);
  if (ctx.gt)
    WriteSource(w, "ground_truth", ctx.gt->source, "rows", ctx.gt->t.size(), ctx.gt->t.front(),
                ctx.gt->t.back(), ctx.gt_keep);
}

/// What a shard writes in its "shard" member and which tasks it runs (RunOptions::Shard).
struct ShardPlan {
  RunOptions::Shard shard;
  std::size_t first = 0, end = 0;                          ///< its block of tasks [first, end)
  std::vector<std::pair<std::string, FileDigest>> inputs;  ///< each input file and its digest
  /// FNV-1a 64 of the shard document's bytes as they go to the sink, up to and including the
  /// bracket that closes "tasks": written after it as the last member, "shard_fnv1a_64", which
  /// imuconv merge checks (so that a damaged or edited element is refused, not merged).
  Fnv1a64 content_hash;
};

/// The shard's block of tasks: units are the shortest runs of consecutive tasks that no
/// reference to an earlier task crosses (a task's results stay in the process that computed
/// them), and shard k of n takes units [k*U/n, (k+1)*U/n).
std::pair<std::size_t, std::size_t> ShardBlock(const PipelineSpec& s,
                                               const RunOptions::Shard& shard) {
  const std::size_t n = s.tasks.size();
  std::unordered_map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < n; ++i) index.emplace(s.tasks[i]->name, i);
  // earliest[i]: the earliest task that task i or a later one is or refers to.
  std::vector<std::size_t> earliest(n + 1, n);
  for (std::size_t j = n; j-- > 0;) {
    std::size_t e = j;
    s.tasks[j]->references([&](const std::string& name, const std::string&) {
      if (const auto it = index.find(name); it != index.end()) e = std::min(e, it->second);
    });
    earliest[j] = std::min(e, earliest[j + 1]);
  }
  std::vector<std::size_t> starts;  // a unit starts at i when nothing from i on refers before i
  for (std::size_t i = 0; i < n; ++i)
    if (earliest[i] == i) starts.push_back(i);
  starts.push_back(n);
  const std::size_t units = starts.size() - 1;
  const auto at = [&](std::size_t k) { return starts[k * units / shard.count]; };
  return {at(shard.index), at(shard.index + 1)};
}

void WriteShard(JsonWriter& w, const ShardPlan& plan, std::size_t tasks) {
  w.key("shard");
  w.begin_object();
  w.key("index");
  w.unsigned_integer(plan.shard.index);
  w.key("count");
  w.unsigned_integer(plan.shard.count);
  w.key("tasks");
  w.unsigned_integer(tasks);
  w.key("first_task");
  w.unsigned_integer(plan.first);
  w.key("end_task");
  w.unsigned_integer(plan.end);
  // The kernels' SIMD instance this CPU runs: instances round the last bits differently (FMA or
  // not), so imuconv merge refuses shards computed by different ones.
  w.key("kernel_instance");
  w.string(kernels::IsaName(kernels::BestIsa()));
  w.key("inputs");
  w.begin_array();
  for (const auto& [file, digest] : plan.inputs) {
    w.begin_object();
    w.key("file");
    w.string(file);
    w.key("bytes");
    w.unsigned_integer(digest.bytes);
    w.key("fnv1a_64");
    w.string(digest.hash.hex());
    w.end_object();
  }
  w.end_array();
  w.end_object();
}

/// Stage "execute and stream": one task's object; its results are kept when a later task
/// names it.
void RunTask(RunContext& ctx, const Task& t, JsonWriter& w) {
  w.begin_object();
  w.key("name");
  w.string(t.name);
  w.key("type");
  w.string(t.type);
  if (!t.description.empty()) {
    w.key("description");
    w.string(t.description);
  }
  TaskResult res;
  res.type = t.type;
  t.run(ctx, w, res);
  w.end_object();
  if (ctx.kept(t.name)) ctx.results[t.name] = std::move(res);
}

void Execute(RunContext& ctx, ShardPlan* plan) {
  JsonWriter w(ctx.out.text(), 0, {}, JsonWriter::NonFinite::Throw, ctx.out.form());
  w.begin_object();
  if (plan) WriteShard(w, *plan, ctx.spec.tasks.size());
  WriteHead(ctx, w);
  w.key("tasks");
  w.begin_array();
  for (std::size_t i = 0; i < ctx.spec.tasks.size(); ++i) {
    if (plan && (i < plan->first || i >= plan->end)) continue;
    const auto& t = ctx.spec.tasks[i];
    try {
      // JSON has no NaN or infinity: the writer fails a task that produced one (naming the
      // output pointer) rather than writing null.
      RunTask(ctx, *t, w);
    } catch (const ConfigError&) {
      throw;
    } catch (const ReadError&) {
      throw;
    } catch (const TaskFailure&) {
      throw;
    } catch (const SinkFailure&) {
      throw;
    } catch (const std::exception& e) {
      throw TaskFailure(ctx.spec.file + ": " + t->pointer + " (task '" + t->name +
                        "'): " + e.what());
    }
    ctx.out.flush(false);
  }
  w.end_array();
  if (plan) {
    // Everything up to here (the "shard" member, the head, the elements, the closing bracket)
    // has passed through the hashing sink once this flush returns.
    ctx.out.flush(true);
    w.key("shard_fnv1a_64");
    w.string(plan->content_hash.hex());
  }
  w.end_object();
  if (ctx.out.form() == JsonWriter::Form::kText) ctx.out.text() += "\n";
  ctx.out.flush(true);
}

void FillStats(const RunContext& ctx, RunOptions::Stats& stats) {
  stats.records = ctx.out.records();
  stats.kept_records = stats.kept_bytes = 0;
  for (const auto& [name, r] : ctx.results) {
    stats.kept_records += r.meas.size() + r.props.size();
    for (const auto& m : r.meas) stats.kept_bytes += KeptBytes(m);
    for (const auto& pr : r.props) stats.kept_bytes += KeptBytes(pr);
  }
}

/// RunToText, in either of the writer's forms (text, or value events for RunToArrays).
void RunToSink(const Pipeline& p, const Registry& reg, const RunOptions& options,
               const TextSink& sink, JsonWriter::Form form) {
  std::optional<ShardPlan> plan;
  if (options.shard) {
    if (options.shard->count == 0 || options.shard->index >= options.shard->count)
      throw Error("shard " + std::to_string(options.shard->index) + "/" +
                  std::to_string(options.shard->count) + ": expected K/N with 0 <= K < N");
    if (form != JsonWriter::Form::kText) throw Error("a shard is written as JSON text only");
    plan.emplace();
    plan->shard = *options.shard;
    std::tie(plan->first, plan->end) = ShardBlock(p.spec(), *options.shard);
  }
  // A shard's bytes are hashed on their way to the sink (ShardPlan::content_hash).
  const TextSink hashing_sink = [&](std::string_view text) {
    plan->content_hash.add(text.data(), text.size());
    sink(text);
  };
  Output out(plan ? hashing_sink : sink, options.threads, form);
  RunContext ctx(p.spec(), reg, options, out);
  ctx.referenced = ReferencedTasks(ctx.spec);
  CheckRegistry(ctx);
  LoadData(ctx);
  if (options.log) {
    for (const auto& w : ctx.imu.warnings) *options.log << "warning: " << w << "\n";
    if (ctx.gt)  // the ground truth's rotations against the gyro
      for (const auto& w :
           PoseGyroWarnings(ctx.imu.samples, *ctx.gt, ctx.spec.file + ": /ground_truth"))
        *options.log << "warning: " << w << "\n";
  }
  CheckTimes(ctx);
  CheckKeptMemory(
      ctx.spec, ctx.referenced, [&](const std::string& f) { return ctx.files.at(f).size(); },
      options.max_kept_bytes);
  if (options.check_only) return;
  if (plan)
    for (const auto& f : p.input_files()) plan->inputs.emplace_back(f, DigestFile(f));
  Execute(ctx, plan ? &*plan : nullptr);
  if (options.stats) FillStats(ctx, *options.stats);
}

void LoadRegistry(const Pipeline& p, const RunOptions& options, Registry& reg) {
  std::vector<std::string> dirs = options.plugin_dirs;
  dirs.insert(dirs.end(), p.plugin_dirs().begin(), p.plugin_dirs().end());
  // A plugin claiming another one's id is an error unless the user or the pipeline opts in;
  // the output's "plugins" list then names the file that won.
  LoadOptions lo;
  lo.allow_override = options.allow_plugin_override || p.spec().allow_plugin_override;
  const auto issues = reg.load_search_path(dirs, lo);
  if (options.log)
    for (const auto& i : issues)
      *options.log << "warning: plugin " << Printable(i.file) << ": " << i.message << "\n";
}

}  // namespace

void RunToText(const Pipeline& p, const Registry& reg, const RunOptions& options,
               const TextSink& sink) {
  RunToSink(p, reg, options, sink, JsonWriter::Form::kText);
}

void RunToText(const Pipeline& p, const RunOptions& options, const TextSink& sink) {
  Registry reg;
  LoadRegistry(p, options, reg);
  RunToText(p, reg, options, sink);
}

ResultArrays RunToArrays(const Pipeline& p, const Registry& reg, const RunOptions& options,
                         const std::function<void()>& started) {
  detail::EventCollector collector("the output of " + Printable(p.file()));
  bool first = true;
  RunToSink(
      p, reg, options,
      [&](std::string_view events) {
        if (first && started) started();
        first = false;
        collector.feed(events);
      },
      JsonWriter::Form::kEvents);
  if (options.check_only) return {};
  return collector.finish();
}

ResultArrays RunToArrays(const Pipeline& p, const RunOptions& options,
                         const std::function<void()>& started) {
  Registry reg;
  LoadRegistry(p, options, reg);
  return RunToArrays(p, reg, options, started);
}

json Run(const Pipeline& p, const Registry& reg, const RunOptions& options) {
  std::string text;
  RunToText(p, reg, options, [&](std::string_view s) { text.append(s.data(), s.size()); });
  return json::parse(text);
}

json Run(const Pipeline& p, const RunOptions& options) {
  std::string text;
  RunToText(p, options, [&](std::string_view s) { text.append(s.data(), s.size()); });
  return json::parse(text);
}

}  // namespace imuconv::pipeline
