// Running a parsed pipeline: registry checks, data loading, time checks, then the tasks.
//
// The output document is streamed: each task writes its part with a JsonWriter as it runs,
// and the text goes to the caller's sink in pieces (about 1 MiB, or one interval's text).
// Independent intervals (the keyframe intervals of a preintegrate task, unchained propagation
// by preintegration) are computed and formatted on a thread pool (ThreadPool::ordered_for);
// each interval's results and text depend on that interval only and go to the sink in index
// order, so the document is the same byte for byte for any thread count. An interval's
// record is kept after it is written only when a later task names the task (results.h).
#include <algorithm>
#include <cstdio>
#include <cmath>
#include <iomanip>
#include <map>
#include <ostream>
#include <sstream>

#include <unordered_map>

#include "imuconv/bridge.h"
#include "imuconv/pipeline/json_writer.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/printable.h"
#include "imuconv/so3.h"
#include "input_checks.h"
#include "intervals.h"
#include "measurement_file.h"
#include "plugins_used.h"
#include "results.h"
#include "run_util.h"
#include "spec.h"
#include "thread_pool.h"

#ifndef IMUCONV_VERSION
#define IMUCONV_VERSION "unknown"
#endif

namespace imuconv::pipeline {
namespace {

constexpr const char* kRef = "preint_reference";
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
// Output text is handed to the sink in pieces of about this size.
constexpr std::size_t kFlushBytes = 1u << 20;

double RotationErrorDeg(const Mat3& a, const Mat3& b) { return so3::Log(a.transpose() * b).norm() * kRadToDeg; }

// ---- output pieces (the JSON forms of json_io.h, written directly) -------------------------
void WriteState(JsonWriter& w, const ImuState& x) {
  const Eigen::Vector4d q = so3::ToQuaternionWxyz(x.R);
  w.begin_object();
  w.key("p");
  w.vector(x.p);
  w.key("q_wxyz");
  w.vector(q);
  w.key("v");
  w.vector(x.v);
  w.key("bg");
  w.vector(x.bg);
  w.key("ba");
  w.vector(x.ba);
  w.end_object();
}

void WriteBias(JsonWriter& w, const Vec3& bg, const Vec3& ba) {
  w.begin_object();
  w.key("bg");
  w.vector(bg);
  w.key("ba");
  w.vector(ba);
  w.end_object();
}

void WriteDelta(JsonWriter& w, const PreintIncrement& d, bool with_R = true) {
  const Eigen::Vector4d q = so3::ToQuaternionWxyz(d.dR);
  w.begin_object();
  w.key("q_wxyz");
  w.vector(q);
  if (with_R) {
    w.key("R");
    w.matrix(d.dR);
  }
  w.key("dp");
  w.vector(d.dp);
  w.key("dv");
  w.vector(d.dv);
  w.key("dbg");
  w.vector(d.dbg);
  w.key("dba");
  w.vector(d.dba);
  w.key("rotation_angle_deg");
  w.number(so3::Log(d.dR).norm() * kRadToDeg);
  w.end_object();
}

/// {"convention", "blocks", "matrix"}.
template <typename M>
void WriteChart(JsonWriter& w, const M& m, const std::string& convention, const std::vector<std::string>& blocks) {
  w.begin_object();
  w.key("convention");
  w.string(convention);
  w.key("blocks");
  w.string_list(blocks);
  w.key("matrix");
  w.matrix(m);
  w.end_object();
}

/// {"rows": {"convention", "blocks"}, "cols": {...}, "matrix"}.
template <typename M>
void WriteMixed(JsonWriter& w, const M& m, const std::string& row_convention, const std::vector<std::string>& row_blocks,
                const std::string& col_convention, const std::vector<std::string>& col_blocks) {
  w.begin_object();
  for (auto [k, c, b] : {std::tuple<const char*, const std::string*, const std::vector<std::string>*>{"rows", &row_convention, &row_blocks},
                         {"cols", &col_convention, &col_blocks}}) {
    w.key(k);
    w.begin_object();
    w.key("convention");
    w.string(*c);
    w.key("blocks");
    w.string_list(*b);
    w.end_object();
  }
  w.key("matrix");
  w.matrix(m);
  w.end_object();
}

/// {"convention", "blocks", "vector"}.
template <typename V>
void WriteChartVector(JsonWriter& w, const V& v, const std::string& convention, const std::vector<std::string>& blocks) {
  w.begin_object();
  w.key("convention");
  w.string(convention);
  w.key("blocks");
  w.string_list(blocks);
  w.key("vector");
  w.vector(v);
  w.end_object();
}

/// The "FILE: POINTER: message" error of one task at run time.
class TaskFailure : public Error {
 public:
  using Error::Error;
};

/// The sink could not take the output (e.g. a full disk): reported as it is, not as a task's.
class SinkFailure : public Error {
 public:
  using Error::Error;
};

class Runner {
 public:
  Runner(const PipelineSpec& s, const Registry& reg, const RunOptions& opt, const TextSink& sink)
      : s_(s), reg_(reg), opt_(opt), sink_(sink), pool_(opt.threads), referenced_(ReferencedTasks(s)) {
    for (const auto& t : s_.tasks) by_name_.emplace(t.name, &t);
  }

  void Run() {
    CheckRegistry();
    LoadData();
    CheckTimes();
    CheckKeptMemory(s_, referenced_, [&](const std::string& f) { return files_.at(f).size(); }, opt_.max_kept_bytes);
    if (opt_.check_only) return;
    JsonWriter w(buf_);
    w.begin_object();
    w.key("imuconv_version");
    w.string(IMUCONV_VERSION);
    w.key("pipeline");
    w.string(s_.file);
    if (!s_.description.empty()) {
      w.key("description");
      w.string(s_.description);
    }
    if (origin_ns_) {
      w.key("time_origin_ns");
      w.integer(*origin_ns_);
    }
    w.key("times");
    w.string(origin_ns_ ? "seconds relative to time_origin_ns; *_abs_ns are absolute nanoseconds" : "seconds, as given");
    w.key("gravity");
    w.vector(s_.gravity);
    w.key("noise");
    w.value(NoiseToJson(s_.noise));
    WritePlugins(w);
    // Only the part of the data the tasks need is read into memory: say which.
    if (have_imu_) {
      w.key("imu");
      w.begin_object();
      w.key("source");
      w.string(imu_.source);
      w.key("samples");
      w.unsigned_integer(imu_.samples.size());
      w.key("t_first");
      w.number(imu_.samples.front().t);
      w.key("t_last");
      w.number(imu_.samples.back().t);
      WriteKept(w, imu_keep_);
      w.end_object();
    }
    if (gt_) {
      w.key("ground_truth");
      w.begin_object();
      w.key("source");
      w.string(gt_->source);
      w.key("rows");
      w.unsigned_integer(gt_->t.size());
      w.key("t_first");
      w.number(gt_->t.front());
      w.key("t_last");
      w.number(gt_->t.back());
      WriteKept(w, gt_keep_);
      w.end_object();
    }
    w.key("tasks");
    w.begin_array();
    for (const auto& t : s_.tasks) {
      try {
        // JSON has no NaN or infinity: the writer fails a task that produced one (naming
        // the output pointer) rather than writing null.
        RunTask(t, w);
      } catch (const ConfigError&) {
        throw;
      } catch (const ReadError&) {
        throw;
      } catch (const TaskFailure&) {
        throw;
      } catch (const SinkFailure&) {
        throw;
      } catch (const std::exception& e) {
        throw TaskFailure(s_.file + ": " + t.pointer + " (task '" + t.name + "'): " + e.what());
      }
      Flush(false);
    }
    w.end_array();
    w.end_object();
    buf_ += "\n";
    Flush(true);
    if (opt_.stats) {
      opt_.stats->records = records_;
      opt_.stats->kept_records = opt_.stats->kept_bytes = 0;
      for (const auto& [name, r] : results_) {
        opt_.stats->kept_records += r.meas.size() + r.props.size();
        for (const auto& m : r.meas) opt_.stats->kept_bytes += KeptBytes(m);
        for (const auto& pr : r.props) opt_.stats->kept_bytes += KeptBytes(pr);
      }
    }
  }

 private:
  const PipelineSpec& s_;
  const Registry& reg_;
  const RunOptions& opt_;
  const TextSink& sink_;
  ThreadPool pool_;
  std::string buf_;  // output not yet handed to the sink
  ImuData imu_;
  bool have_imu_ = false;
  std::optional<std::int64_t> origin_ns_;
  std::optional<GroundTruth> gt_;
  std::optional<std::pair<double, double>> imu_keep_, gt_keep_;  // the time ranges read into memory
  // Results of the tasks a later task names (referenced_), and nothing else.
  std::unordered_map<std::string, std::string> referenced_;
  std::unordered_map<std::string, const TaskSpec*> by_name_;
  std::map<std::string, TaskResult> results_;
  std::map<std::string, std::vector<MeasRecord>> files_;
  std::size_t records_ = 0;  // interval results written (RunOptions::Stats)

  void Flush(bool all) {
    if (buf_.empty() || (!all && buf_.size() < kFlushBytes)) return;
    Sink(buf_);
    buf_.clear();
  }

  void Sink(std::string_view text) {
    try {
      sink_(text);
    } catch (const std::exception& e) {
      throw SinkFailure(e.what());
    }
  }

  /// Writes n elements of the open array of `w`, element k by write_one(writer, k) (which
  /// may compute it first): run on the pool, each into its own string by its own writer, and
  /// handed to the sink in order as soon as it is there (at most a window of elements
  /// ahead). The text is the same as writing them one after the other into `w`.
  /// consumed(k) runs on the calling thread, in order, once element k is in the sink; what
  /// write_one(., k) left in a slot of index k % Window() is still there for it.
  template <typename F, typename G>
  void WriteElements(JsonWriter& w, std::size_t n, const F& write_one, const G& consumed) {
    const int depth = w.content_depth();
    const std::string base = w.container_pointer();
    const std::string first_sep = w.element_separator(true), sep = w.element_separator(false);
    const std::size_t window = Window();
    std::vector<std::string> slots(std::min(window, n));
    pool_.ordered_for(
        n, window,
        [&](std::size_t k) {
          std::string& text = slots[k % window];
          text = k == 0 ? first_sep : sep;
          JsonWriter cw(text, depth, base + "/" + std::to_string(k));
          write_one(cw, k);
        },
        [&](std::size_t k) {
          if (k == 0) Flush(true);  // what comes before the elements
          Sink(slots[k % window]);
          slots[k % window] = std::string();  // a long element's text is not held on to
          ++records_;
          consumed(k);
        });
    w.skip_elements(n);
  }
  /// Elements in flight at most in WriteElements.
  std::size_t Window() const { return 16 * static_cast<std::size_t>(pool_.size()); }

  // ---- checks against the registry --------------------------------------------------
  void CheckId(Checker& c, PluginKind kind, const std::string& id, const std::string& pointer) {
    CheckPluginId(c, reg_, kind, id, pointer);
  }

  void CheckCovConvention(Checker& c, const CovSpec& cov, PluginKind kind, const std::string& target) {
    if (!cov.given) return;
    const std::string conv = cov.m().convention.value_or(target);
    if (cov.m().convention) {
      CheckId(c, kind, conv, cov.m().pointer + "/convention");
      if (!reg_.has(kind, conv)) return;
    }
    if (cov.m().blocks && reg_.has(kind, conv)) {
      const auto expect = Blocks(reg_, kind, conv);
      if (*cov.m().blocks != expect)
        c.error(cov.m().pointer + "/blocks", "blocks [" + Join(*cov.m().blocks) + "] do not match the block order of '" + conv +
                                               "': [" + Join(expect) + "]");
    }
  }

  void CheckRegistry() {
    Checker c(s_.file);
    for (const auto& t : s_.tasks) {
      const std::string& p = t.pointer;
      if (const auto* x = std::get_if<PropagateTask>(&t.body)) {
        CheckId(c, PluginKind::Propagator, x->propagator, p + "/propagator");
        CheckId(c, PluginKind::StateConvention, x->convention, p + "/state_convention");
        if (reg_.has(PluginKind::StateConvention, x->convention))
          CheckCovConvention(c, x->cov, PluginKind::StateConvention, x->convention);
      } else if (const auto* x = std::get_if<PreintegrateTask>(&t.body)) {
        CheckId(c, x->native ? PluginKind::Preintegrator : PluginKind::Propagator, x->method_id, x->method_pointer);
        for (std::size_t i = 0; i < x->conventions.size(); ++i)
          CheckId(c, PluginKind::PreintConvention, x->conventions[i], x->conventions_pointer + "/" + std::to_string(i));
      } else if (const auto* x = std::get_if<PropByPreintTask>(&t.body)) {
        CheckId(c, PluginKind::StateConvention, x->convention, p + "/state_convention");
        if (reg_.has(PluginKind::StateConvention, x->convention))
          CheckCovConvention(c, x->cov, PluginKind::StateConvention, x->convention);
      } else if (const auto* x = std::get_if<ConvertTask>(&t.body)) {
        using W = ConvertTask::What;
        const bool state_kind = x->what == W::StateJacobian || x->what == W::StateCovariance || x->what == W::StateTransition;
        const PluginKind kind = state_kind ? PluginKind::StateConvention : PluginKind::PreintConvention;
        if (x->from) CheckId(c, kind, *x->from, x->from_pointer);
        CheckId(c, kind, x->to, x->to_pointer);
        if (x->matrix && x->matrix->convention && x->from && *x->matrix->convention != *x->from)
          c.error(x->matrix->pointer + "/convention",
                  "the matrix is in '" + *x->matrix->convention + "' but \"from\" is '" + *x->from + "'");
        if (x->matrix && x->from && reg_.has(kind, *x->from)) {
          CovSpec cs;
          cs.given = true;
          cs.in = x->matrix;
          CheckCovConvention(c, cs, kind, *x->from);
        }
        if (x->source_task) {
          const auto it = results_type(*x->source_task);
          const bool ok = state_kind ? (it == "propagate" || it == "propagate_by_preintegration") : it == "preintegrate";
          if (!ok)
            c.error(x->source_pointer + "/task", "task '" + *x->source_task + "' is a " + it + " task; a " + x->what_name +
                                                     " conversion takes its matrix from " +
                                                     (state_kind ? "a propagate or propagate_by_preintegration task"
                                                                 : "a preintegrate task"));
        }
      } else if (const auto* x = std::get_if<ResidualTask>(&t.body)) {
        CheckId(c, PluginKind::StateConvention, x->convention, p + "/state_convention");
      } else if (const auto* x = std::get_if<BiasUpdateTask>(&t.body)) {
        for (std::size_t i = 0; i < x->charts.size(); ++i)
          CheckId(c, PluginKind::PreintConvention, x->charts[i], x->charts_pointer + "/" + std::to_string(i));
      }
    }
    c.throw_if_errors();
  }

  std::string results_type(const std::string& name) const {
    const auto it = by_name_.find(name);
    return it == by_name_.end() ? "?" : it->second->type;
  }

  void WritePlugins(JsonWriter& w) const {
    // Provenance: which file (and version) each plugin the tasks used came from, so that a
    // plugin overriding another's id is visible in the output.
    w.key("plugins");
    w.begin_array();
    for (const PluginInfo* info : PluginsUsed(s_, reg_, files_)) {
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
  }

  static void WriteKept(JsonWriter& w, const std::optional<std::pair<double, double>>& keep) {
    if (!keep) return;
    w.key("kept_range");
    w.begin_line_array();
    w.number(keep->first);
    w.number(keep->second);
    w.end_array();
  }

  // ---- data -----------------------------------------------------------------------------
  /// The time range the propagate and preintegrate tasks integrate over, if any.
  std::optional<std::pair<double, double>> ImuRange() const {
    std::optional<std::pair<double, double>> r;
    const auto add = [&](double a, double b) {
      r = r ? std::make_pair(std::min(r->first, a), std::max(r->second, b)) : std::make_pair(a, b);
    };
    for (const auto& t : s_.tasks) {
      if (const auto* x = std::get_if<PropagateTask>(&t.body)) add(x->interval.front(), x->interval.back());
      if (const auto* x = std::get_if<PreintegrateTask>(&t.body)) add(x->intervals.front(), x->intervals.back());
    }
    return r;
  }

  void LoadData() {
    // Only the samples the tasks integrate over are kept (the readers still check every
    // line and keep one sample beyond each end, for interpolation).
    const auto imu_range = ImuRange();
    if (s_.imu) {
      const ImuSourceSpec& src = *s_.imu;
      ReadOptions ro;
      ro.timing = src.timing;
      ro.keep = imu_range;
      if (src.format == ImuSourceSpec::Format::Euroc) {
        imu_ = ReadEurocImu(src.path, src.origin_ns, ro);
        imu_keep_ = imu_range;
      } else if (src.format == ImuSourceSpec::Format::Csv) {
        imu_ = ReadCsvImu(src.path, src.csv, ro);
        imu_keep_ = imu_range;
      } else {
        // Inline samples (timing checked when parsed, at their pointers) are all in memory.
        TimeOrigin o;
        o.unit = src.csv.time_unit;
        if (src.csv.time_origin) o.value = *src.csv.time_origin;
        imu_.source = "inline";
        for (std::size_t i = 0; i < src.inline_raw.size(); ++i) {
          ImuSample smp = src.inline_raw[i];
          smp.t = o.relative_seconds(src.inline_t[i]);
          if (!imu_.samples.empty() && !(smp.t > imu_.samples.back().t))
            throw ConfigError(s_.file, {{src.pointer + "/samples/" + std::to_string(src.inline_index[i]) + "/0",
                                         "time is too close to the previous sample's to be told apart in seconds"}});
          imu_.samples.push_back(smp);
        }
        if (src.csv.time_origin) imu_.origin = o;
      }
      have_imu_ = true;
      if (imu_.origin) origin_ns_ = imu_.origin->nanoseconds();
      // With a kept range, fewer than 2 samples means the range misses the data: CheckTimes
      // says which time is outside.
      if (imu_.samples.size() < 2 && !(imu_keep_ && !imu_.samples.empty()))
        throw ReadError(imu_.source, 0, "has " + std::to_string(imu_.samples.size()) + " IMU sample(s); at least 2 are needed");
    }
    // Measurement files (on the IMU data's time axis, so after it).
    for (const auto& t : s_.tasks) {
      const MeasurementsSpec* m = nullptr;
      if (const auto* x = std::get_if<PropByPreintTask>(&t.body)) m = &x->meas;
      if (const auto* x = std::get_if<ResidualTask>(&t.body)) m = &x->meas;
      if (const auto* x = std::get_if<BiasUpdateTask>(&t.body)) m = &x->meas;
      if (m && !m->file.empty() && !files_.count(m->file)) files_[m->file] = ReadMeasurementFile(m->file, reg_, origin_ns_);
    }
    if (s_.gt) {
      TimeOrigin o;
      if (imu_.origin)
        o = *imu_.origin;
      else
        o.unit = TimeUnit::s;  // inline samples without an origin: GT stamps taken as absolute
      // Ground truth is looked up at interval ends and at the measurements' times.
      auto range = imu_range;
      for (const auto& [file, records] : files_)
        for (const auto& r : records)
          for (const auto& tm : {r.t_s, r.t_e})
            if (tm) range = range ? std::make_pair(std::min(range->first, *tm), std::max(range->second, *tm)) : std::make_pair(*tm, *tm);
      ReadOptions ro;
      ro.timing = s_.gt->timing;
      ro.keep = range;
      gt_ = ReadEurocGroundTruth(s_.gt->path, o, ro);
      gt_keep_ = range;
    }
  }

  // ---- checks against the data ---------------------------------------------------------
  void CheckTime(Checker& c, double t, const std::string& pointer) {
    const double t0 = imu_.samples.front().t, t1 = imu_.samples.back().t;
    if (t < t0)
      c.error(pointer, "t = " + Num(t, 10) + " s is before the first IMU sample (t = " + Num(t0, 10) + " s; times are relative to the time origin)");
    else if (t > t1)
      c.error(pointer, "t = " + Num(t, 10) + " s is after the last IMU sample (t = " + Num(t1, 10) + " s; times are relative to the time origin)");
  }

  /// Where the ground truth ends, for a time it does not cover. Only the rows around the
  /// times the tasks use are read, but every such time is in that range: a time before the
  /// first row read is before the file's first row (and after the last, after its last).
  std::string GtUncovered(double t) const {
    return "ground truth does not cover t = " + Num(t, 10) + " s (" + Printable(gt_->source) +
           (t < gt_->t.front() ? " starts at t = " + Num(gt_->t.front(), 10) : " ends at t = " + Num(gt_->t.back(), 10)) +
           " s)";
  }

  void CheckGt(Checker& c, double t, const std::string& pointer) {
    if (!gt_) return;
    if (!(t >= gt_->t.front() && t <= gt_->t.back())) c.error(pointer, GtUncovered(t));
  }

  /// Every keyframe within the IMU data. Generated keyframes increase, so the first one and
  /// the first one past the data say all there is (one message, not one per keyframe).
  void CheckIntervalTimes(Checker& c, const IntervalsSpec& iv) {
    if (iv.form != IntervalsSpec::Form::Generated) {
      for (std::size_t i = 0; i < iv.size(); ++i) CheckTime(c, iv.time(i), iv.pointer_of(i));
      return;
    }
    CheckTime(c, iv.front(), iv.pointer_of(0));
    const double t1 = imu_.samples.back().t;
    if (!(iv.back() > t1)) return;
    std::size_t lo = 0, hi = iv.size() - 1;  // the first keyframe after t1 is in (lo, hi]
    while (hi - lo > 1) {
      const std::size_t mid = lo + (hi - lo) / 2;
      (iv.time(mid) > t1 ? hi : lo) = mid;
    }
    if (iv.time(lo) > t1) hi = lo;
    c.error(iv.pointer_of(iv.size() - 1), "t = " + Num(iv.time(hi), 10) + " s is after the last IMU sample (t = " +
                                              Num(t1, 10) + " s; times are relative to the time origin): keyframe " +
                                              std::to_string(hi) + " of " + std::to_string(iv.size()) +
                                              (hi + 1 < iv.size() ? " and every later one up to end" : std::string()));
  }

  void CheckTimes() {
    Checker c(s_.file);
    for (const auto& t : s_.tasks) {
      const IntervalsSpec* iv = nullptr;
      const StateSpec* st = nullptr;
      const BiasSpec* bs = nullptr;
      if (const auto* x = std::get_if<PropagateTask>(&t.body)) {
        iv = &x->interval;
        st = &x->start;
        if (x->compare_gt.value_or(false) && iv->size()) CheckGt(c, iv->back(), iv->pointer_of(iv->size() - 1));
      }
      if (const auto* x = std::get_if<PreintegrateTask>(&t.body)) {
        iv = &x->intervals;
        bs = &x->bias;
      }
      if (!iv || iv->size() < 2) continue;
      if (!have_imu_) continue;  // reported by the parser
      CheckIntervalTimes(c, *iv);
      if (st && st->ground_truth) CheckGt(c, iv->front(), st->pointer);
      // The bias at every interval start: the ground truth spans one range, so the first
      // and the last start decide.
      if (bs && bs->ground_truth) {
        CheckGt(c, iv->front(), bs->pointer);
        if (iv->size() > 2) CheckGt(c, iv->time(iv->size() - 2), bs->pointer);
      }
    }
    c.throw_if_errors();
  }

  // ---- helpers ---------------------------------------------------------------------------
  /// The keys t_start, t_end (and their *_abs_ns) of the open object.
  void WriteTimes(JsonWriter& w, std::optional<double> ts, std::optional<double> te) const {
    if (ts) {
      w.key("t_start");
      w.number(*ts);
    }
    if (te) {
      w.key("t_end");
      w.number(*te);
    }
    if (imu_.origin) {
      if (ts)
        if (auto a = imu_.origin->absolute_ns(*ts)) {
          w.key("t_start_abs_ns");
          w.integer(*a);
        }
      if (te)
        if (auto a = imu_.origin->absolute_ns(*te)) {
          w.key("t_end_abs_ns");
          w.integer(*a);
        }
    }
  }
  /// {t_start, t_end, ...} as an object.
  void WriteInterval(JsonWriter& w, std::optional<double> ts, std::optional<double> te) const {
    w.begin_object();
    WriteTimes(w, ts, te);
    w.end_object();
  }

  SampleWindow Window(double ts, double te) const {
    SampleWindow w;
    const Status st = MakeWindow(imu_.samples.data(), imu_.samples.size(), ts, te, w);
    if (!st.ok()) throw Error(st.message());
    return w;
  }

  const std::vector<std::string>& BlocksOf(PluginKind kind, const std::string& id) const { return reg_.info(kind, id).blocks; }

  void StateChart(JsonWriter& w, const Mat15& m, const std::string& conv) const {
    WriteChart(w, m, conv, BlocksOf(PluginKind::StateConvention, conv));
  }
  /// Covariances the pipeline computed are checked before they are written (input_checks.h).
  void CovChart(JsonWriter& w, const Mat15& m, const std::string& conv, const std::vector<std::string>& blocks) const {
    CheckOutputCovariance(m, w.pointer() + "/matrix");
    WriteChart(w, m, conv, blocks);
  }
  void StateCovChart(JsonWriter& w, const Mat15& m, const std::string& conv) const {
    CovChart(w, m, conv, BlocksOf(PluginKind::StateConvention, conv));
  }
  void PreintCovChart(JsonWriter& w, const Mat15& m, const std::string& conv) const {
    CovChart(w, m, conv, BlocksOf(PluginKind::PreintConvention, conv));
  }

  Mat15 StartCov(const CovSpec& cov, const std::string& conv, const ImuState& x) const {
    if (!cov.given) return Mat15::Zero();
    if (cov.m().convention && *cov.m().convention != conv) return reg_.convert_covariance(*cov.m().convention, conv, x, cov.m().m);
    return cov.m().m;
  }

  ImuState GtAt(double t, const std::string& pointer) const {
    if (!gt_) throw TaskFailure(s_.file + ": " + pointer + ": there is no /ground_truth");
    auto x = gt_->at(t);
    if (!x) throw TaskFailure(s_.file + ": " + pointer + ": " + GtUncovered(t));
    return *x;
  }

  struct GtError {
    double pos = 0, rot = 0, vel = 0;
  };
  /// A prediction against the ground truth: the errors and the left-chart error vector.
  struct GtComparison {
    ImuState gt;
    GtError e;
    Vec15 d = Vec15::Zero();
  };
  static GtComparison Compare(const ImuState& pred, const ImuState& gt) {
    GtComparison c;
    c.gt = gt;
    c.e.pos = (pred.p - gt.p).norm();
    c.e.rot = RotationErrorDeg(gt.R, pred.R);
    c.e.vel = (pred.v - gt.v).norm();
    LeftLocal(gt, pred, c.d);
    return c;
  }
  static void WriteComparison(JsonWriter& w, const GtComparison& c) {
    static const std::vector<std::string> kLeftBlocks = {"p", "theta", "v", "bg", "ba"};
    w.begin_object();
    w.key("state");
    WriteState(w, c.gt);
    w.key("position_error_m");
    w.number(c.e.pos);
    w.key("rotation_error_deg");
    w.number(c.e.rot);
    w.key("velocity_error_mps");
    w.number(c.e.vel);
    w.key("error_left");
    WriteChartVector(w, c.d, "left", kLeftBlocks);
    w.end_object();
  }

  const std::vector<MeasRecord>& Measurements(const MeasurementsSpec& m) const {
    if (!m.task.empty()) return results_.at(m.task).meas;
    return files_.at(m.file);
  }
  std::string MeasurementsName(const MeasurementsSpec& m) const {
    return m.task.empty() ? "file " + m.file : "task '" + m.task + "'";
  }
  void WriteMeasurementsSource(JsonWriter& w, const MeasurementsSpec& m) const {
    w.key("measurements");
    if (m.task.empty()) {
      w.begin_object();
      w.key("file");
      w.string(m.file);
      w.end_object();
    } else {
      w.string(m.task);
    }
  }

  Preintegrated Integrate(const PreintegrateTask& p, const SampleWindow& w, const Vec3& bg, const Vec3& ba) const {
    return p.native ? PreintegrateNative(reg_, p.method_id, w, bg, ba, s_.noise)
                    : PreintegrateByPropagation(reg_, p.method_id, w, bg, ba, s_.noise);
  }

  /// One measurement: times, bias estimate, increment, J_bias and cov in preint_reference and
  /// in each of `conventions`.
  void WriteMeasurement(JsonWriter& w, const MeasRecord& r, std::size_t k, const std::vector<std::string>& conventions) const {
    const Preintegrated& m = r.m;
    w.begin_object();
    w.key("index");
    w.unsigned_integer(k);
    WriteTimes(w, r.t_s, r.t_e);
    w.key("dt");
    w.number(m.dt);
    if (r.n_knots) {
      w.key("n_knots");
      w.unsigned_integer(r.n_knots);
    }
    w.key("bias_estimate");
    WriteBias(w, m.bg_hat, m.ba_hat);
    w.key("delta");
    WriteDelta(w, m.delta, !s_.omit.R);
    const OmitSpec& omit = s_.omit;
    const bool reference = conventions.empty() || !omit.reference;
    const auto& ref_blocks = BlocksOf(PluginKind::PreintConvention, kRef);
    if (reference && !omit.J_bias) {
      w.key("J_bias");
      WriteMixed(w, m.J_bias, kRef, NavLabels(ref_blocks), kRef, BiasLabels(ref_blocks));
    }
    if (reference && !omit.cov) {
      w.key("cov");
      CovChart(w, m.cov, kRef, ref_blocks);
    }
    if (!conventions.empty() && !(omit.J_bias && omit.cov)) {
      w.key("expressed");
      w.begin_object();
      for (const auto& c : conventions) {
        const PreintegratedIn in = Express(reg_, m, c);
        const auto& jb = BlocksOf(PluginKind::PreintConvention, in.jacobian_convention);
        w.key(c);
        w.begin_object();
        if (!omit.J_bias) {
          w.key("J_bias");
          WriteMixed(w, in.J_bias, in.jacobian_convention, NavLabels(jb), in.jacobian_convention, BiasLabels(jb));
        }
        if (!omit.cov) {
          w.key("cov");
          PreintCovChart(w, in.cov, in.convention);
        }
        w.end_object();
      }
      w.end_object();
    }
    w.end_object();
  }

  // ---- tasks -----------------------------------------------------------------------------
  void RunTask(const TaskSpec& t, JsonWriter& w) {
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
    if (const auto* x = std::get_if<PropagateTask>(&t.body)) RunPropagate(t, *x, w, res);
    if (const auto* x = std::get_if<PreintegrateTask>(&t.body)) RunPreintegrate(t, *x, w, res);
    if (const auto* x = std::get_if<PropByPreintTask>(&t.body)) RunPropByPreint(t, *x, w, res);
    if (const auto* x = std::get_if<ConvertTask>(&t.body)) RunConvert(t, *x, w);
    if (const auto* x = std::get_if<ResidualTask>(&t.body)) RunResidual(t, *x, w);
    if (const auto* x = std::get_if<BiasUpdateTask>(&t.body)) RunBiasUpdate(t, *x, w);
    w.end_object();
    if (Kept(t)) results_[t.name] = std::move(res);
  }

  /// A later task names this one: its results are kept (else written and dropped).
  bool Kept(const TaskSpec& t) const { return referenced_.count(t.name) > 0; }

  void RunPropagate(const TaskSpec& t, const PropagateTask& p, JsonWriter& w, TaskResult& res) {
    const double ts = p.interval.front(), te = p.interval.back();
    PropagationInput in;
    in.x_s = p.start.ground_truth ? GtAt(ts, p.start.pointer) : p.start.x;
    in.cov_s = StartCov(p.cov, p.convention, in.x_s);
    in.noise = s_.noise;
    in.gravity = s_.gravity;
    in.window = Window(ts, te);
    const PropagationResult r = reg_.propagate(p.propagator, p.convention, in);
    const bool compare = p.compare_gt.value_or(gt_ && gt_->at(te).has_value());
    std::optional<GtComparison> cmp;
    if (compare) cmp = Compare(r.x_e, GtAt(te, t.pointer + "/interval/t_end"));
    w.key("propagator");
    w.string(p.propagator);
    w.key("state_convention");
    w.string(p.convention);
    w.key("interval");
    WriteInterval(w, ts, te);
    w.key("n_knots");
    w.unsigned_integer(in.window.size());
    w.key("x_s");
    WriteState(w, in.x_s);
    if (!s_.omit.cov) {
      w.key("cov_s");
      StateCovChart(w, in.cov_s, p.convention);
    }
    w.key("x_e");
    WriteState(w, r.x_e);
    if (!s_.omit.Phi) {
      w.key("Phi");
      StateChart(w, r.Phi, p.convention);
    }
    if (!s_.omit.cov) {
      w.key("cov");
      StateCovChart(w, r.cov, p.convention);
    }
    if (cmp) {
      w.key("ground_truth");
      WriteComparison(w, *cmp);
    }
    ++records_;
    res.props.push_back({in.x_s, r.x_e, r.Phi, r.cov, p.convention, ts, te});
    if (opt_.summary) {
      std::ostream& o = *opt_.summary;
      o << "propagate '" << t.name << "': " << p.propagator << " over [" << Num(ts) << ", " << Num(te) << "] s ("
        << in.window.size() << " knots), state convention " << p.convention;
      if (cmp) o << "; vs ground truth: position " << Num(cmp->e.pos, 4) << " m, rotation " << Num(cmp->e.rot, 4) << " deg";
      o << "\n";
    }
  }

  void RunPreintegrate(const TaskSpec& t, const PreintegrateTask& p, JsonWriter& w, TaskResult& res) {
    res.preint = &p;
    const IntervalsSpec& iv = p.intervals;
    const std::size_t n = iv.size() < 2 ? 0 : iv.size() - 1;
    // Every interval on its own, computed and written on the pool; its record is kept only
    // when a later task uses it.
    const bool keep = Kept(t);
    if (keep) res.meas.resize(n);
    const auto compute = [&](std::size_t k, MeasRecord& r) {
      const double ts = iv.time(k), te = iv.time(k + 1);
      Vec3 bg = p.bias.bg, ba = p.bias.ba;
      if (p.bias.ground_truth) {
        const ImuState g = GtAt(ts, p.bias.pointer);
        bg = g.bg;
        ba = g.ba;
      }
      const SampleWindow win = Window(ts, te);
      r.m = Integrate(p, win, bg, ba);
      r.t_s = ts;
      r.t_e = te;
      r.n_knots = win.size();
    };
    w.key("method");
    w.begin_object();
    w.key(p.native ? "preintegrator" : "propagator");
    w.string(p.method_id);
    w.end_object();
    w.key("bias");
    if (p.bias.ground_truth)
      w.string("ground_truth at each interval start");
    else
      WriteBias(w, p.bias.bg, p.bias.ba);
    w.key("conventions");
    w.string_list(p.conventions);
    w.key("measurements");
    w.begin_array();
    double total = 0;  // summed in index order, whatever the thread count
    std::vector<double> dts(std::min(Window(), n));
    WriteElements(
        w, n,
        [&](JsonWriter& cw, std::size_t k) {
          MeasRecord local;
          MeasRecord& r = keep ? res.meas[k] : local;
          compute(k, r);
          WriteMeasurement(cw, r, k, p.conventions);
          dts[k % Window()] = r.m.dt;
        },
        [&](std::size_t k) { total += dts[k % Window()]; });
    w.end_array();
    if (opt_.summary) {
      *opt_.summary << "preintegrate '" << t.name << "': " << n << " measurement(s) over " << Num(total) << " s by "
                    << (p.native ? "native preintegrator " : "propagation with ") << p.method_id
                    << (p.conventions.empty() ? std::string() : ", expressed in " + Join(p.conventions));
      if (iv.form == IntervalsSpec::Form::Generated && iv.short_last)
        *opt_.summary << "; the last interval, [" << Num(iv.time(n - 1), 10) << ", " << Num(iv.end, 10) << "] s, is the "
                      << Num(iv.end - iv.time(n - 1)) << " s left after " << n - 1 << " whole step(s) of " << Num(iv.step)
                      << " s";
      *opt_.summary << "\n";
    }
  }

  /// Totals of a propagate_by_preintegration task over its steps, in index order.
  struct StepTotals {
    std::size_t ngt = 0;
    double se_p = 0, se_r = 0, max_p = 0, max_r = 0, sum_dt = 0, sum_dp = 0, sum_ang = 0;
  };

  void RunPropByPreint(const TaskSpec& t, const PropByPreintTask& p, JsonWriter& w, TaskResult& res) {
    const auto& ms = Measurements(p.meas);
    const std::size_t n = ms.size();
    const bool keep = Kept(t);
    if (keep) res.props.resize(n);
    // Step k from its start state (and covariance) to its end: the start is the previous
    // step's end when chained, else given or the ground truth (independent steps).
    const auto step = [&](std::size_t k, const ImuState& x_s, const Mat15& cov_s, PropRecord& pr,
                          std::optional<GtComparison>& cmp) {
      const MeasRecord& r = ms[k];
      const std::string where = p.meas.task.empty() ? r.pointer : p.meas.pointer + " (measurement " + std::to_string(k) + ")";
      const PropagationResult out = PropagateByPreintegration(reg_, r.m, x_s, cov_s, p.convention, s_.gravity);
      const bool compare = p.compare_gt.value_or(gt_ && r.t_e && gt_->at(*r.t_e).has_value());
      if (compare) {
        if (!r.t_e) throw TaskFailure(s_.file + ": " + where + ": comparing with ground truth needs t_end");
        cmp = Compare(out.x_e, GtAt(*r.t_e, where));
      }
      pr = {x_s, out.x_e, out.Phi, out.cov, p.convention, r.t_s, r.t_e};
    };
    const auto start_state = [&](std::size_t k) {
      if (!p.start.ground_truth) return p.start.x;
      const MeasRecord& r = ms[k];
      if (!r.t_s)
        throw TaskFailure(s_.file + ": " + p.start.pointer + ": starting from ground truth needs t_start of " +
                          MeasurementsName(p.meas) + " measurement " + std::to_string(k));
      return GtAt(*r.t_s, p.start.pointer);
    };
    const auto write_step = [&](JsonWriter& sw, std::size_t k, const PropRecord& pr, const std::optional<GtComparison>& cmp) {
      const MeasRecord& r = ms[k];
      sw.begin_object();
      sw.key("index");
      sw.unsigned_integer(k);
      WriteTimes(sw, r.t_s, r.t_e);
      sw.key("dt");
      sw.number(r.m.dt);
      sw.key("x_s");
      WriteState(sw, pr.x_s);
      sw.key("x_e");
      WriteState(sw, pr.x_e);
      if (!s_.omit.Phi) {
        sw.key("Phi");
        StateChart(sw, pr.Phi, p.convention);
      }
      if (!s_.omit.cov) {
        sw.key("cov");
        StateCovChart(sw, pr.cov, p.convention);
      }
      if (cmp) {
        sw.key("ground_truth");
        WriteComparison(sw, *cmp);
      }
      sw.end_object();
    };
    // The summary table is printed row by row as the steps are written (nothing per step is
    // held), and the totals are summed in index order.
    std::ostream* o = opt_.summary;
    if (o) {
      *o << "\npropagate_by_preintegration '" << t.name << "': " << MeasurementsName(p.meas) << ", state convention "
         << p.convention << ", "
         << (p.start.ground_truth ? (p.chain ? "chained from the ground truth at the first keyframe"
                                             : "each interval from the ground truth at its start")
                                  : (p.chain ? "chained from the given start state" : "each interval from the given start state"))
         << "\n";
    }
    // Whether any step is compared with the ground truth decides the table's columns; the
    // rows are printed before all steps are known, so the header shows them when a
    // comparison is possible at all.
    const bool gt_columns = gt_ && p.compare_gt.value_or(true);
    if (o) {
      *o << "     k   t_start[s]   dt[s]    |dp|[m]   angle[deg]";
      if (gt_columns) *o << "   pos.err[m]   rot.err[deg]";
      *o << "\n";
    }
    StepTotals tot;
    const auto row = [&](std::size_t k, const std::optional<GtComparison>& cmp) {
      const MeasRecord& r = ms[k];
      const double dp = r.m.delta.dp.norm(), ang = so3::Log(r.m.delta.dR).norm() * kRadToDeg;
      tot.sum_dt += r.m.dt;
      tot.sum_dp += dp;
      tot.sum_ang += ang;
      if (cmp) {
        ++tot.ngt;
        tot.se_p += cmp->e.pos * cmp->e.pos;
        tot.se_r += cmp->e.rot * cmp->e.rot;
        tot.max_p = std::max(tot.max_p, cmp->e.pos);
        tot.max_r = std::max(tot.max_r, cmp->e.rot);
      }
      if (!o) return;
      char buf[256];
      if (r.t_s)
        std::snprintf(buf, sizeof buf, "%6zu %12.3f %7.4f %10.5f %12.5f", k, *r.t_s, r.m.dt, dp, ang);
      else
        std::snprintf(buf, sizeof buf, "%6zu %12s %7.4f %10.5f %12.5f", k, "-", r.m.dt, dp, ang);
      std::string line = buf;
      if (cmp) {
        std::snprintf(buf, sizeof buf, " %12.3e %14.3e", cmp->e.pos, cmp->e.rot);
        line += buf;
      }
      *o << line << "\n";
    };
    WriteMeasurementsSource(w, p.meas);
    w.key("state_convention");
    w.string(p.convention);
    w.key("start");
    if (p.start.ground_truth)
      w.string("ground_truth");
    else
      WriteState(w, p.start.x);
    w.key("chain");
    w.boolean(p.chain);
    w.key("steps");
    w.begin_array();
    if (p.chain) {
      // One after the other (each starts at the previous end), written straight into w: the
      // text WriteElements would splice. Only the previous step is held.
      PropRecord prev;
      for (std::size_t k = 0; k < n; ++k) {
        PropRecord pr;
        std::optional<GtComparison> cmp;
        if (k == 0) {
          const ImuState x = start_state(0);
          step(0, x, StartCov(p.cov, p.convention, x), pr, cmp);
        } else {
          step(k, prev.x_e, prev.cov, pr, cmp);
        }
        write_step(w, k, pr, cmp);
        ++records_;
        row(k, cmp);
        if (keep) res.props[k] = pr;
        prev = std::move(pr);
        Flush(false);
      }
    } else {
      std::vector<std::optional<GtComparison>> cmps(std::min(Window(), n));
      WriteElements(
          w, n,
          [&](JsonWriter& sw, std::size_t k) {
            PropRecord local;
            PropRecord& pr = keep ? res.props[k] : local;
            std::optional<GtComparison>& cmp = cmps[k % Window()];
            cmp.reset();
            const ImuState x = start_state(k);
            step(k, x, StartCov(p.cov, p.convention, x), pr, cmp);
            write_step(sw, k, pr, cmp);
          },
          [&](std::size_t k) { row(k, cmps[k % Window()]); });
    }
    w.end_array();
    if (tot.ngt) {
      const double ngt = static_cast<double>(tot.ngt);
      w.key("ground_truth_summary");
      w.begin_object();
      w.key("intervals");
      w.unsigned_integer(tot.ngt);
      w.key("rms_position_error_m");
      w.number(std::sqrt(tot.se_p / ngt));
      w.key("max_position_error_m");
      w.number(tot.max_p);
      w.key("rms_rotation_error_deg");
      w.number(std::sqrt(tot.se_r / ngt));
      w.key("max_rotation_error_deg");
      w.number(tot.max_r);
      w.end_object();
    }
    if (!o) return;
    char buf[256];
    const std::string label = " total (" + std::to_string(n) + ")";
    std::snprintf(buf, sizeof buf, "%-19s %7.4f %10.5f %12.5f", label.c_str(), tot.sum_dt, tot.sum_dp, tot.sum_ang);
    *o << buf;
    if (tot.ngt) {
      const double ngt = static_cast<double>(tot.ngt);
      std::snprintf(buf, sizeof buf, " %12.3e %14.3e   rms over %zu interval(s)\n", std::sqrt(tot.se_p / ngt),
                    std::sqrt(tot.se_r / ngt), tot.ngt);
      *o << buf;
      std::snprintf(buf, sizeof buf, "%-19s %7s %10s %12s %12.3e %14.3e   max\n", "", "", "", "", tot.max_p, tot.max_r);
      *o << buf;
    } else {
      *o << "\n";
    }
  }

  void RunConvert(const TaskSpec& t, const ConvertTask& p, JsonWriter& w) {
    using W = ConvertTask::What;
    const bool state_kind = p.what == W::StateJacobian || p.what == W::StateCovariance || p.what == W::StateTransition;
    std::string from = p.from.value_or("");
    ImuState xs, xe;
    PreintIncrement d;
    Mat15 M = Mat15::Zero();
    if (p.source_task) {
      const TaskResult& src = results_.at(*p.source_task);
      const std::size_t count = state_kind ? src.props.size() : src.meas.size();
      if (p.source_index >= count)
        throw TaskFailure(s_.file + ": " + p.source_pointer + "/index: task '" + *p.source_task + "' has " +
                          std::to_string(count) + " result(s); index " + std::to_string(p.source_index) + " is out of range");
      std::string src_conv;
      if (state_kind) {
        const PropRecord& r = src.props[p.source_index];
        xs = r.x_s;
        xe = r.x_e;
        src_conv = r.convention;
        M = p.what == W::StateTransition ? r.Phi : r.cov;
      } else {
        const MeasRecord& r = src.meas[p.source_index];
        d = r.m.delta;
        M = r.m.cov;
        src_conv = kRef;
      }
      if (!from.empty() && from != src_conv)
        throw TaskFailure(s_.file + ": " + p.from_pointer + ": the source's matrices are in '" + src_conv + "', not '" + from +
                          "' (leave \"from\" out to use the source's convention)");
      from = src_conv;
    } else {
      if (p.state) xs = *p.state;
      if (p.state_end) xe = *p.state_end;
      if (p.increment) d = *p.increment;
      if (p.matrix) M = p.matrix->m;
    }
    const PluginKind kind = state_kind ? PluginKind::StateConvention : PluginKind::PreintConvention;
    const auto& bf = BlocksOf(kind, from);
    const auto& bt = BlocksOf(kind, p.to);
    // The result first (it may throw), then the output.
    Mat15 result;
    const ImuState& x_at = p.source_task ? xe : xs;  // state Jacobian / covariance: at the source's end state
    switch (p.what) {
      case W::StateJacobian: result = reg_.conversion(from, p.to, x_at); break;
      case W::StateCovariance: result = reg_.convert_covariance(from, p.to, x_at, M); break;
      case W::StateTransition: result = reg_.convert_transition(from, p.to, xs, xe, M); break;
      case W::IncrementJacobian: result = reg_.preint_conversion(from, p.to, d); break;
      case W::IncrementCovariance: {
        const Mat15 J = reg_.preint_conversion(from, p.to, d);
        result = J * M * J.transpose();
        result = (0.5 * (result + result.transpose())).eval();
        break;
      }
    }
    w.key("what");
    w.string(p.what_name);
    w.key("from");
    w.string(from);
    w.key("to");
    w.string(p.to);
    if (p.source_task) {
      w.key("source");
      w.begin_object();
      w.key("task");
      w.string(*p.source_task);
      w.key("index");
      w.unsigned_integer(p.source_index);
      w.end_object();
    }
    switch (p.what) {
      case W::StateJacobian:
        w.key("state");
        WriteState(w, x_at);
        w.key("result");
        WriteMixed(w, result, p.to, bt, from, bf);
        break;
      case W::StateCovariance:
        w.key("state");
        WriteState(w, x_at);
        w.key("input");
        CovChart(w, M, from, bf);
        w.key("result");
        CovChart(w, result, p.to, bt);
        break;
      case W::StateTransition:
        w.key("state");
        WriteState(w, xs);
        w.key("state_end");
        WriteState(w, xe);
        w.key("input");
        WriteChart(w, M, from, bf);
        w.key("result");
        WriteChart(w, result, p.to, bt);
        break;
      case W::IncrementJacobian:
        w.key("increment");
        WriteDelta(w, d, !s_.omit.R);
        w.key("result");
        WriteMixed(w, result, p.to, bt, from, bf);
        break;
      case W::IncrementCovariance:
        w.key("increment");
        WriteDelta(w, d, !s_.omit.R);
        w.key("input");
        CovChart(w, M, from, bf);
        w.key("result");
        CovChart(w, result, p.to, bt);
        break;
    }
    if (opt_.summary) *opt_.summary << "convert '" << t.name << "': " << p.what_name << " from " << from << " to " << p.to << "\n";
  }

  std::vector<std::size_t> Selected(const std::vector<MeasRecord>& ms, const std::optional<std::size_t>& index,
                                    const std::string& pointer, const std::string& what) const {
    if (!index) {
      std::vector<std::size_t> all(ms.size());
      for (std::size_t i = 0; i < ms.size(); ++i) all[i] = i;
      return all;
    }
    if (*index >= ms.size())
      throw TaskFailure(s_.file + ": " + pointer + "/index: " + what + " has " + std::to_string(ms.size()) +
                        " measurement(s); index " + std::to_string(*index) + " is out of range");
    return {*index};
  }

  void RunResidual(const TaskSpec& t, const ResidualTask& p, JsonWriter& w) {
    const auto& ms = Measurements(p.meas);
    const auto sel = Selected(ms, p.index, t.pointer, MeasurementsName(p.meas));
    if ((!p.start.ground_truth || !p.end.ground_truth) && sel.size() > 1)
      throw TaskFailure(s_.file + ": " + t.pointer + ": explicit start/end states go with one measurement; give \"index\" (" +
                        MeasurementsName(p.meas) + " has " + std::to_string(ms.size()) + ")");
    const std::vector<std::string> rblocks = {"theta", "p", "v", "bg", "ba"};
    const std::string rconv = "residual_" + p.kind_name;
    const auto& sb = BlocksOf(PluginKind::StateConvention, p.convention);
    const auto& ib = BlocksOf(PluginKind::PreintConvention, kRef);
    w.key("kind");
    w.string(p.kind_name);
    WriteMeasurementsSource(w, p.meas);
    w.key("state_convention");
    w.string(p.convention);
    w.key("residuals");
    w.begin_array();
    double sum_m2 = 0;
    std::size_t n_m2 = 0;
    for (std::size_t k : sel) {
      const MeasRecord& r = ms[k];
      const auto state_at = [&](const StateSpec& s, std::optional<double> t_at, const char* which) {
        if (!s.ground_truth) return s.x;
        if (!t_at)
          throw TaskFailure(s_.file + ": " + s.pointer + ": ground truth needs the measurement's " + which + " time");
        return GtAt(*t_at, s.pointer);
      };
      const ImuState xs = state_at(p.start, r.t_s, "start"), xe = state_at(p.end, r.t_e, "end");
      const Residual res = ComputeResidual(reg_, p.kind, r.m, xs, xe, p.convention, s_.gravity);
      w.begin_object();
      w.key("index");
      w.unsigned_integer(k);
      WriteTimes(w, r.t_s, r.t_e);
      w.key("x_s");
      WriteState(w, xs);
      w.key("x_e");
      WriteState(w, xe);
      w.key("r");
      WriteChartVector(w, res.r, rconv, rblocks);
      w.key("H_start");
      WriteMixed(w, res.H_start, rconv, rblocks, p.convention, sb);
      w.key("H_end");
      WriteMixed(w, res.H_end, rconv, rblocks, p.convention, sb);
      w.key("H_increment");
      WriteMixed(w, res.H_increment, rconv, rblocks, kRef, ib);
      w.key("cov");
      CovChart(w, res.cov, rconv, rblocks);
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
    if (opt_.summary) {
      *opt_.summary << "residual '" << t.name << "' (" << p.kind_name << "): " << sel.size() << " residual(s)";
      if (n_m2) *opt_.summary << ", mean r^T cov^-1 r = " << Num(sum_m2 / static_cast<double>(n_m2), 4) << " (15 dof)";
      *opt_.summary << "\n";
    }
  }

  void RunBiasUpdate(const TaskSpec& t, const BiasUpdateTask& p, JsonWriter& w) {
    const auto& ms = Measurements(p.meas);
    const auto sel = Selected(ms, p.index, t.pointer, MeasurementsName(p.meas));
    const PreintegrateTask* origin = p.meas.task.empty() ? nullptr : results_.at(p.meas.task).preint;
    WriteMeasurementsSource(w, p.meas);
    w.key("updates");
    w.begin_array();
    double max_rot = 0, max_dp = 0, max_dv = 0;
    for (std::size_t k : sel) {
      const MeasRecord& r = ms[k];
      const Vec3 bg = p.relative ? Vec3(r.m.bg_hat + p.bg) : p.bg;
      const Vec3 ba = p.relative ? Vec3(r.m.ba_hat + p.ba) : p.ba;
      w.begin_object();
      w.key("index");
      w.unsigned_integer(k);
      WriteTimes(w, r.t_s, r.t_e);
      w.key("bias_estimate");
      WriteBias(w, r.m.bg_hat, r.m.ba_hat);
      w.key("new_bias");
      WriteBias(w, bg, ba);
      std::optional<Preintegrated> re;
      if (p.reintegrate && origin && r.t_s && r.t_e) {
        re = Integrate(*origin, Window(*r.t_s, *r.t_e), bg, ba);
        w.key("reintegrated");
        MeasRecord rr;
        rr.m = *re;
        rr.t_s = r.t_s;
        rr.t_e = r.t_e;
        WriteMeasurement(w, rr, k, {});
      }
      w.key("first_order");
      w.begin_object();
      for (const auto& c : p.charts) {
        const PreintIncrement d = BiasCorrectedDelta(reg_, r.m, c, bg, ba);
        w.key(c);
        w.begin_object();
        w.key("delta");
        WriteDelta(w, d, !s_.omit.R);
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
          max_rot = std::max(max_rot, rot);
          max_dp = std::max(max_dp, edp);
          max_dv = std::max(max_dv, edv);
        }
        w.end_object();
      }
      w.end_object();
      w.end_object();
    }
    w.end_array();
    if (opt_.summary) {
      *opt_.summary << "bias_update '" << t.name << "': " << sel.size() << " measurement(s), first order in " << Join(p.charts);
      if (p.reintegrate && origin)
        *opt_.summary << "; first order vs re-integration: max " << Num(max_rot, 3) << " deg, " << Num(max_dp, 3) << " m (dp), "
                      << Num(max_dv, 3) << " m/s (dv)";
      *opt_.summary << "\n";
    }
  }
};

}  // namespace

void RunToText(const Pipeline& p, const Registry& reg, const RunOptions& options, const TextSink& sink) {
  Runner r(p.spec(), reg, options, sink);
  r.Run();
}

void RunToText(const Pipeline& p, const RunOptions& options, const TextSink& sink) {
  std::vector<std::string> dirs = options.plugin_dirs;
  dirs.insert(dirs.end(), p.plugin_dirs().begin(), p.plugin_dirs().end());
  Registry reg;
  // A plugin claiming another one's id is an error unless the user or the pipeline opts in;
  // the output's "plugins" list then names the file that won.
  LoadOptions lo;
  lo.allow_override = options.allow_plugin_override || p.spec().allow_plugin_override;
  const auto issues = reg.load_search_path(dirs, lo);
  if (options.log)
    for (const auto& i : issues) *options.log << "warning: plugin " << Printable(i.file) << ": " << i.message << "\n";
  RunToText(p, reg, options, sink);
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
