#include "experiments.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>

#include "imuconv/bridge.h"
#include "imuconv/check/difference.h"
#include "imuconv/printable.h"
#include "imuconv/window.h"

namespace imuconv::experiment {
namespace {

// The preintegrators the note compares with (GTSAM's two schemes) and the increment chart
// each reports its covariance in: GTSAM's own, where the note reads GTSAM's numbers.
constexpr const char* kSchemes[2] = {"manifold", "tangent"};
constexpr const char* kSchemeCharts[2] = {"gtsam_manifold", "gtsam_tangent"};
// The propagation side's chart: the note's left error state (its eqs. left-dpr..left-dba).
constexpr const char* kStateChart = "left";

// Trials run in batches: the threads share one batch, whose differences are then summed in
// trial order (so the sums do not depend on which thread ran which trial).
constexpr int kBatch = 64;

bool IsBias(const std::string& label) { return label == "bg" || label == "ba"; }

/// The labels of a chart's blocks, all of them or only the state (non-bias) or bias ones.
enum class Which { all, state, bias };
std::vector<std::string> Labels(const BlockLabels& labels, Which which) {
  std::vector<std::string> out;
  for (const char* l : labels) {
    const std::string s = l;
    if (which == Which::all || (which == Which::bias) == IsBias(s)) out.push_back(s);
  }
  return out;
}

/// Where each of the two matrices of a comparison comes from, per trial.
enum class Source { increment_jacobian, increment_cov, transition, state_cov };

struct Plan {
  Comparison c;
  Source source;
  int scheme;  ///< index into kSchemes
};

/// A comparison of `experiment` on scheme s's preintegrator, its matrices from `source`.
Plan SchemePlan(const char* experiment, Source source, int s) {
  Plan p;
  p.source = source;
  p.scheme = s;
  p.c.experiment = experiment;
  p.c.preintegrator = kSchemes[s];
  return p;
}

/// The eight comparisons (or four of one experiment), in the order of the note's figures.
std::vector<Plan> MakePlans(const Registry& reg, const Options& o) {
  std::vector<Plan> plans;
  if (o.preint_by_prop) {
    for (const Source src : {Source::increment_jacobian, Source::increment_cov})
      for (int s = 0; s < 2; ++s) {
        Plan p = SchemePlan("preint-by-prop", src, s);
        p.c.reference = kSchemes[s];
        const auto conv = reg.increment_convention(kSchemeCharts[s]);
        if (src == Source::increment_jacobian) {
          p.c.matrix = "J_bias";
          p.c.chart = conv->jacobian_convention();
          p.c.row_blocks = Labels(reg.increment_convention(p.c.chart)->labels(), Which::state);
          p.c.col_blocks = Labels(conv->labels(), Which::bias);
          p.c.scaled_metric = "relative_above_floor";
        } else {
          p.c.matrix = "cov";
          p.c.chart = conv->id();
          p.c.row_blocks = p.c.col_blocks = Labels(conv->labels(), Which::all);
          p.c.scaled_metric = "correlation";
        }
        plans.push_back(p);
      }
  }
  if (o.prop_by_preint) {
    const auto left = reg.state_convention(kStateChart);
    for (const Source src : {Source::transition, Source::state_cov})
      for (int s = 0; s < 2; ++s) {
        Plan p = SchemePlan("prop-by-preint", src, s);
        p.c.reference = o.propagator;
        p.c.chart = kStateChart;
        p.c.matrix = src == Source::transition ? "Phi" : "cov";
        p.c.row_blocks = p.c.col_blocks = Labels(left->labels(), Which::all);
        p.c.scaled_metric = src == Source::transition ? "relative_above_floor" : "correlation";
        plans.push_back(p);
      }
  }
  return plans;
}

struct Methods {
  PreintegrationMethod propagator;
  PreintegrationMethod schemes[2];
};

/// A trial's reference and compared matrices, one pair per plan.
struct Pair {
  Eigen::MatrixXd ref, user;
};

SampleWindow Window(const std::vector<ImuSample>& s, const char* what) {
  SampleWindow w;
  const Status st = MakeWindow(s.data(), s.size(), s.front().t, s.back().t, w);
  if (!st.ok()) throw Error(std::string("cannot window the ") + what + ": " + st.message());
  return w;
}

std::vector<Pair> RunTrial(const Registry& reg, const Methods& m, const std::vector<Plan>& plans,
                           const Options& o, std::uint64_t index) {
  const Trial t = MakeTrial(o.seed, index, o.spec);
  const std::vector<ImuSample> prop_samples = Subdivide(t.samples, o.propagator_substeps);
  const std::vector<ImuSample> pre_samples =
      o.input == PreintegratorInput::mid ? MidSampleInput(t.samples) : t.samples;
  const SampleWindow w_prop = Window(prop_samples, "propagator's samples");
  const SampleWindow w_pre = Window(pre_samples, "preintegrators' samples");
  const Vec3& bg = t.x_s.bg;
  const Vec3& ba = t.x_s.ba;

  Preintegrated native[2];
  for (int s = 0; s < 2; ++s) native[s] = Preintegrate(reg, m.schemes[s], w_pre, bg, ba, t.noise);
  Preintegrated by_propagation;
  if (o.preint_by_prop) by_propagation = Preintegrate(reg, m.propagator, w_prop, bg, ba, t.noise);
  PropagationResult propagated;
  PropagationResult by_preintegration[2];
  if (o.prop_by_preint) {
    // In kStateChart (left), where the trial's start covariance is given.
    propagated =
        reg.propagate(o.propagator, kStateChart, {t.x_s, t.cov_s_left, t.noise, t.gravity, w_prop});
    for (int s = 0; s < 2; ++s)
      by_preintegration[s] =
          PropagateByPreintegration(reg, native[s], t.x_s, t.cov_s_left, kStateChart, t.gravity);
  }

  std::vector<Pair> pairs;
  for (const Plan& p : plans) {
    const int s = p.scheme;
    switch (p.source) {
      case Source::increment_jacobian:
      case Source::increment_cov: {
        // GTSAM's numbers (the preintegrator) are the reference, as in the note's Figure 1.
        const Preintegrated ref = Express(reg, native[s], kSchemeCharts[s]);
        const Preintegrated est = Express(reg, by_propagation, kSchemeCharts[s]);
        if (p.source == Source::increment_jacobian)
          pairs.push_back({ref.J_bias, est.J_bias});
        else
          pairs.push_back({ref.cov, est.cov});
        break;
      }
      case Source::transition:  // the propagator is the reference (Figure 2)
        pairs.push_back({propagated.Phi, by_preintegration[s].Phi});
        break;
      case Source::state_cov:
        pairs.push_back({propagated.cov, by_preintegration[s].cov});
        break;
    }
  }
  return pairs;
}

}  // namespace

Result RunExperiments(const Registry& reg, const Options& o) {
  if (o.trials < 1 || o.trials > kMaxTrials)
    throw Error("trials: " + std::to_string(o.trials) + ", expected 1 to " +
                std::to_string(kMaxTrials));
  if (o.threads < 1 || o.threads > kMaxThreads)
    throw Error("threads: " + std::to_string(o.threads) + ", expected 1 to " +
                std::to_string(kMaxThreads));
  if (!o.preint_by_prop && !o.prop_by_preint) throw Error("no experiment chosen");
  if (!reg.has(PluginKind::Propagator, o.propagator)) {
    std::string known;
    for (const auto& id : reg.ids(PluginKind::Propagator)) known += " " + id;
    throw Error("unknown propagator " + Printable(o.propagator) + "; known:" + known);
  }
  Methods m;
  m.propagator = ResolvePreintegrationMethod(reg, PluginKind::Propagator, o.propagator);
  for (int s = 0; s < 2; ++s)
    m.schemes[s] = ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, kSchemes[s]);

  std::vector<Plan> plans = MakePlans(reg, o);
  const std::size_t n_plans = plans.size();
  std::vector<Eigen::MatrixXd> sum_note(n_plans), sum_scaled(n_plans);
  std::vector<double> max_note(n_plans, 0.0), max_scaled(n_plans, -1.0);
  std::vector<int> worst(n_plans, 0);

  std::vector<std::vector<Pair>> batch(kBatch);
  std::vector<std::exception_ptr> errors(kBatch);
  for (int first = 0; first < o.trials; first += kBatch) {
    const int count = std::min(kBatch, o.trials - first);
    std::fill(errors.begin(), errors.end(), nullptr);
    std::atomic<int> next{0};
    auto work = [&] {
      for (int k = next++; k < count; k = next++) {
        try {
          batch[k] = RunTrial(reg, m, plans, o, static_cast<std::uint64_t>(first + k));
        } catch (...) {
          errors[k] = std::current_exception();
        }
      }
    };
    const int n_threads = std::min(o.threads, count);
    std::vector<std::thread> pool;
    for (int i = 1; i < n_threads; ++i) pool.emplace_back(work);
    work();
    for (auto& th : pool) th.join();

    for (int k = 0; k < count; ++k) {
      if (errors[k]) {
        try {
          std::rethrow_exception(errors[k]);
        } catch (const std::exception& e) {
          throw Error("trial " + std::to_string(first + k) + " (seed " + std::to_string(o.seed) +
                      "): " + e.what());
        }
      }
      for (std::size_t c = 0; c < n_plans; ++c) {
        const Pair& pr = batch[k][c];
        // A non-finite matrix is a defect of a plugin, not a difference to average.
        if (!pr.ref.allFinite() || !pr.user.allFinite())
          throw Error("trial " + std::to_string(first + k) + " (seed " + std::to_string(o.seed) +
                      "): " + plans[c].c.experiment + " " + plans[c].c.matrix + " with " +
                      plans[c].c.preintegrator + ": a non-finite entry in the " +
                      (pr.ref.allFinite() ? "compared" : "reference") + " matrix");
        const Eigen::MatrixXd note = check::NoteEntries(pr.ref, pr.user);
        const Eigen::MatrixXd scaled = plans[c].c.scaled_metric == "correlation"
                                           ? check::CorrelationScaleEntries(pr.ref, pr.user)
                                           : check::RelativeAboveFloorEntries(pr.ref, pr.user);
        if (sum_note[c].size() == 0) {
          sum_note[c] = Eigen::MatrixXd::Zero(note.rows(), note.cols());
          sum_scaled[c] = Eigen::MatrixXd::Zero(note.rows(), note.cols());
        }
        sum_note[c] += note;
        sum_scaled[c] += scaled;
        max_note[c] = std::max(max_note[c], note.maxCoeff());
        if (scaled.maxCoeff() > max_scaled[c]) {
          max_scaled[c] = scaled.maxCoeff();
          worst[c] = first + k;
        }
      }
    }
  }

  Result r;
  r.options = o;
  for (std::size_t c = 0; c < n_plans; ++c) {
    Comparison cmp = plans[c].c;
    cmp.mean_note_d = sum_note[c] / o.trials;
    cmp.mean_scaled_d = sum_scaled[c] / o.trials;
    cmp.note_mean = check::Summarize(cmp.mean_note_d).mean;
    cmp.scaled_mean = check::Summarize(cmp.mean_scaled_d).mean;
    cmp.note_max = max_note[c];
    cmp.scaled_max = max_scaled[c];
    cmp.worst_trial = worst[c];
    r.comparisons.push_back(std::move(cmp));
  }
  return r;
}

}  // namespace imuconv::experiment
