// The problem of imuconv optimize, its solves and re-integration rounds, and the marginal
// covariances (optimize.h).
#include "imuconv/optimize/optimize.h"

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <mutex>
#include <thread>

#include "imuconv/ceres/pose_factors.h"
#include "imuconv/ceres/preintegration_factor.h"
#include "imuconv/ceres/state_block.h"
#include "imuconv/ceres/state_manifold.h"
#include "imuconv/did_you_mean.h"
#include "imuconv/pipeline/interval_samples.h"
#include "imuconv/pipeline/optimize_evaluator.h"
#include "imuconv/printable.h"

namespace imuconv::optimize {

namespace cf = ceres_factors;

namespace {

// Times are relative seconds of ~1e2 magnitude: 1 ns absorbs their rounding (EuRoC's stamps are
// integer nanoseconds), so a keyframe exactly at the last common instant still counts (as nees).
constexpr double kTimeSlack = 1e-9;

// Solver tolerances. The optimum must agree to 1e-8 whichever chart the solver steps in, so the
// solve is run to where the cost no longer changes in its 12th digit (Levenberg-Marquardt
// converges quadratically there: a few iterations more than Ceres's defaults of 1e-6/1e-8).
constexpr double kFunctionTolerance = 1e-12;
constexpr double kGradientTolerance = 1e-12;
constexpr double kParameterTolerance = 1e-12;

std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string Seconds(double s) { return Number(s) + " s"; }

PreintegrationMethod ResolveMethod(const Registry& reg, const std::string& id) {
  if (reg.has(PluginKind::Propagator, id))
    return ResolvePreintegrationMethod(reg, PluginKind::Propagator, id);
  if (reg.has(PluginKind::Preintegrator, id))
    return ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, id);
  std::vector<std::string> known = reg.ids(PluginKind::Preintegrator);
  for (const auto& p : reg.ids(PluginKind::Propagator)) known.push_back(p);
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  throw Error("--method: unknown propagator or preintegrator " + Printable(id) +
              DidYouMean(id, known) + "; known: " + list);
}

double MedianPeriod(const std::vector<ImuSample>& s) {
  std::vector<double> dt(s.size() - 1);
  for (std::size_t i = 1; i < s.size(); ++i) dt[i - 1] = s[i].t - s[i - 1].t;
  std::nth_element(dt.begin(), dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2), dt.end());
  return dt[dt.size() / 2];
}

// The samples of [t_s, t_e] and one on each side (the factor's window interpolates at its ends).
std::vector<ImuSample> SamplesCovering(const std::vector<ImuSample>& s, double t_s, double t_e) {
  auto first = std::upper_bound(s.begin(), s.end(), t_s,
                                [](double t, const ImuSample& x) { return t < x.t; });
  if (first != s.begin()) --first;
  auto last = std::lower_bound(s.begin(), s.end(), t_e,
                               [](const ImuSample& x, double t) { return x.t < t; });
  if (last != s.end()) ++last;
  return {first, last};
}

// The measured pose at t, or an error naming the time (the span was checked; this guards it).
ImuState PoseAt(const pipeline::GroundTruth& poses, double t) {
  const auto x = poses.at(t);
  if (!x) throw Error("keyframe at " + Seconds(t) + " is outside the poses of " + poses.source);
  return *x;
}

void CheckNoise(const ImuNoise& q) {
  const double d[4] = {q.gyro_noise_density, q.accel_noise_density, q.gyro_random_walk,
                       q.accel_random_walk};
  for (const double v : d)
    if (!(v > 0) || !std::isfinite(v))
      throw Error(
          "--noise: each of the four densities must be positive and finite: the factors are "
          "whitened by the covariance they give (the bias rows by the random walks alone)");
}

// A 15x15 diagonal in the chart `labels` orders: each block's variance from its label.
Mat15 PriorCovariance(const BlockLabels& labels, const WeakPriorSigmas& s) {
  Mat15 cov = Mat15::Zero();
  for (int b = 0; b < kBlockCount; ++b) {
    const std::string label = labels[static_cast<std::size_t>(b)];
    const double sigma = label == "theta" ? s.theta_rad
                         : label == "p"   ? s.p_m
                         : label == "v"   ? s.v_mps
                         : label == "bg"  ? s.bg_radps
                                          : s.ba_mps2;
    cov.block<3, 3>(3 * b, 3 * b) = sigma * sigma * Mat3::Identity();
  }
  return cov;
}

std::string TerminationName(ceres::TerminationType t) { return ceres::TerminationTypeToString(t); }

// Ceres logs through glog; a program that never called InitGoogleLogging (this one, a Python
// host) gets its warnings (ceres::Covariance's "rank deficient") on stderr with a banner, while
// everything they say is in the result (covariance_message). Warnings and below are dropped,
// once per process; a host that set a stricter level keeps it.
void QuietCeresLogging() {
  static std::once_flag once;
  std::call_once(once, [] { FLAGS_minloglevel = std::max(FLAGS_minloglevel, google::GLOG_ERROR); });
}

}  // namespace

Result RunOptimize(const Registry& reg, const pipeline::ImuData& imu,
                   const pipeline::GroundTruth& poses, const Options& options) {
  QuietCeresLogging();
  const PreintegrationMethod method = ResolveMethod(reg, options.method);
  if (!reg.has(PluginKind::StateConvention, options.convention))
    throw Error("--convention: unknown state convention " + Printable(options.convention) +
                DidYouMean(options.convention, reg.ids(PluginKind::StateConvention)));
  CheckNoise(options.noise);
  if (!(options.pose_sigma_m >= pipeline::kMinPoseSigma) ||
      !(options.pose_sigma_rad >= pipeline::kMinPoseSigma) ||
      !std::isfinite(options.pose_sigma_m) || !std::isfinite(options.pose_sigma_rad))
    throw Error(std::string("--pose-sigma: both standard deviations must be finite and at least ") +
                pipeline::kMinPoseSigmaText + ", found " + Number(options.pose_sigma_m) + " m, " +
                Number(options.pose_sigma_rad) + " rad");
  if (!(options.reintegrate_gyro > 0) || !(options.reintegrate_accel > 0))
    throw Error("--reintegrate-gyro/--reintegrate-accel: thresholds must be positive");
  if (options.max_rounds < 1) throw Error("--max-rounds: at least one solve");
  if (options.max_iterations < 1) throw Error("--max-iterations: at least one iteration");
  if (imu.samples.size() < 2 || poses.t.size() < 2)
    throw Error("fewer than two IMU samples or poses");

  const double step = options.keyframe_step;
  const double period = MedianPeriod(imu.samples);
  const double t_begin = std::max(imu.samples.front().t, poses.t.front());
  const double t_end = std::min(imu.samples.back().t, poses.t.back());
  const double span = t_end - t_begin;
  if (!(span > 0))
    throw Error("the IMU data (" + imu.source + ", " + Seconds(imu.samples.front().t) + " to " +
                Seconds(imu.samples.back().t) + ") and the poses (" + poses.source + ", " +
                Seconds(poses.t.front()) + " to " + Seconds(poses.t.back()) +
                ", on the IMU's time axis) do not overlap");
  if (!std::isfinite(step) || !(step > 0))
    throw Error("--keyframe-step: " + Seconds(step) + " is not a positive duration");
  if (step < period)
    throw Error("--keyframe-step: " + Seconds(step) + " is shorter than the IMU's sample period (" +
                Seconds(period) + ", the median in " + imu.source +
                "): a factor needs at least one interval");
  if (step > span + kTimeSlack)
    throw Error("--keyframe-step: " + Seconds(step) + " is longer than the " + Seconds(span) +
                " the IMU data (" + imu.source + ") and the poses (" + poses.source +
                ") share: there would be fewer than two keyframes");

  // A count from span and step, before anything is stored per keyframe: a step in the wrong
  // unit, or one over a gap of days, would otherwise allocate until the process dies.
  if (span / step + 1.0 > static_cast<double>(kMaxKeyframes))
    throw Error("--keyframe-step: " + Seconds(step) + " over the " + Seconds(span) +
                " the IMU data (" + imu.source + ") and the poses (" + poses.source +
                ") share gives more than " + std::to_string(kMaxKeyframes) +
                " keyframes, the limit of one solve (a step in the wrong unit?)");

  Result r;
  r.method = options.method;
  r.convention = options.convention;
  r.kind = options.kind == ResidualKind::Gtsam ? "gtsam" : "forster";
  r.keyframe_step = step;
  r.noise = options.noise;
  const BlockLabels labels = reg.state_convention(options.convention)->labels();
  for (const char* l : labels) r.labels.emplace_back(l);

  // Keyframe times by multiplication from the first, so they carry no drift.
  std::vector<double> times;
  for (std::size_t i = 0;; ++i) {
    const double t = t_begin + static_cast<double>(i) * step;
    if (t > t_end + kTimeSlack) break;
    times.push_back(std::min(t, t_end));
  }
  const std::size_t n = times.size();
  // Each factor needs a sample strictly inside its interval (interval_samples.h: over one
  // interpolated step its covariance is singular), whatever the step: a step of one median
  // period still leaves intervals between two samples where the stamps jitter, and every
  // interval in a gap of the data holds none.
  if (const auto empty = pipeline::FindEmptyInterval(
          imu.samples, n, [&times](std::size_t k) { return times[k]; },
          pipeline::IntervalEnds::kExcluded))
    throw Error(
        "--keyframe-step: " +
        pipeline::EmptyIntervalSentence(*empty, pipeline::IntervalEnds::kExcluded, step, n - 1) +
        " (" + imu.source +
        "). A preintegration factor needs one: over a single step its covariance is singular (a "
        "step longer than the longest sample period gives every interval one, unless the "
        "keyframes fall in a gap of the data)");

  // Initial values: the measured pose, the velocity from a central difference of the poses over
  // one keyframe step (clamped to the span), zero biases (the factors' linearization point).
  std::vector<std::array<double, cf::kStateBlockSize>> blocks(n);
  std::vector<ImuState> measured(n);
  for (std::size_t i = 0; i < n; ++i) {
    measured[i] = PoseAt(poses, times[i]);
    const double ta = std::max(t_begin, times[i] - step / 2),
                 tb = std::min(t_end, times[i] + step / 2);
    ImuState x0 = measured[i];
    x0.v = (PoseAt(poses, tb).p - PoseAt(poses, ta).p) / (tb - ta);
    x0.bg.setZero();
    x0.ba.setZero();
    cf::ToStateBlock(x0, blocks[i].data());
  }

  // The factors outlive the problem (its cost functions refer to them): declared first.
  std::vector<std::unique_ptr<cf::PreintegrationFactor>> factors;
  cf::PreintegrationFactorOptions fo;
  fo.kind = options.kind;
  fo.gravity = options.gravity;
  fo.reintegrate_gyro_bias = options.reintegrate_gyro;
  fo.reintegrate_accel_bias = options.reintegrate_accel;
  for (std::size_t i = 0; i + 1 < n; ++i)
    factors.push_back(std::make_unique<cf::PreintegrationFactor>(
        reg, method, SamplesCovering(imu.samples, times[i], times[i + 1]), times[i], times[i + 1],
        options.noise, Vec3::Zero(), Vec3::Zero(), fo));
  r.factors = static_cast<int>(factors.size());

  ceres::Problem problem;  // owns the cost functions and the manifold
  auto* manifold = new cf::StateManifold(reg, options.convention);
  for (auto& b : blocks) problem.AddParameterBlock(b.data(), cf::kStateBlockSize, manifold);
  for (std::size_t i = 0; i + 1 < n; ++i)
    problem.AddResidualBlock(factors[i]->MakeCostFunction(), nullptr, blocks[i].data(),
                             blocks[i + 1].data());
  for (std::size_t i = 0; i < n; ++i)
    problem.AddResidualBlock(cf::MakePoseMeasurement(measured[i].R, measured[i].p,
                                                     options.pose_sigma_m, options.pose_sigma_rad),
                             nullptr, blocks[i].data());
  {
    // The prior in the chart `left`, whatever the solver's convention: its cost, like every
    // other, must not depend on the chart (ceres-api.md's design rules).
    const ImuState x_prior = cf::FromStateBlock(blocks[0].data());
    const BlockLabels left = reg.state_convention("left")->labels();
    problem.AddResidualBlock(
        cf::MakeStatePrior(reg, "left", x_prior, PriorCovariance(left, options.prior)), nullptr,
        blocks[0].data());
  }

  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  so.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  so.max_num_iterations = options.max_iterations;
  so.function_tolerance = kFunctionTolerance;
  so.gradient_tolerance = kGradientTolerance;
  so.parameter_tolerance = kParameterTolerance;
  so.num_threads = 1;  // the same bytes on every run and machine
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  for (int round = 0; round < options.max_rounds; ++round) {
    ceres::Solve(so, &problem, &summary);
    Round rd;
    rd.iterations = static_cast<int>(summary.iterations.size());
    rd.initial_cost = summary.initial_cost;
    rd.final_cost = summary.final_cost;
    rd.termination = TerminationName(summary.termination_type);
    rd.seconds = summary.total_time_in_seconds;
    r.rounds.push_back(rd);
    if (summary.termination_type != ceres::CONVERGENCE) break;  // reported, not re-solved
    if (round + 1 == options.max_rounds) break;
    int moved = 0;
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const ImuState xs = cf::FromStateBlock(blocks[i].data());
      moved += factors[i]->ReintegrateIfMoved(xs.bg, xs.ba) ? 1 : 0;
    }
    r.rounds.back().reintegrated = moved;
    if (moved == 0) break;
  }
  // A cost that overflowed (a pose sigma so small that its information is inf) is no optimum,
  // whatever Ceres's termination says: NaN passes every comparison its convergence tests make.
  const bool finite_cost = std::isfinite(summary.final_cost);
  r.converged = summary.termination_type == ceres::CONVERGENCE && finite_cost;
  r.solver_message = finite_cost ? summary.message
                                 : "the final cost " + Number(summary.final_cost) +
                                       " is not finite (" + summary.message + ")";
  // Factors whose bias still moved beyond the thresholds after the last solve (max_rounds
  // reached): their measurement is first-order corrected, not re-integrated.
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const ImuState xs = cf::FromStateBlock(blocks[i].data());
    const Preintegrated& m = factors[i]->measurement();
    if ((xs.bg - m.bg_hat).norm() > options.reintegrate_gyro ||
        (xs.ba - m.ba_hat).norm() > options.reintegrate_accel)
      ++r.pending_reintegration;
  }

  r.keyframes.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    Keyframe& k = r.keyframes[i];
    k.t = times[i];
    k.x = cf::FromStateBlock(blocks[i].data());
    if (poses.full_state) {
      const ImuState ref = PoseAt(poses, times[i]);
      k.has_reference_bias = true;
      k.ref_bg = ref.bg;
      k.ref_ba = ref.ba;
    }
  }
  r.has_reference_bias = poses.full_state;

  if (options.covariance && r.converged) {
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::SPARSE_QR;
    co.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
    // Each covariance row is solved on its own, by the same operations whichever thread runs
    // it: the bytes do not depend on the thread count (the V1_01 slice at 0.1 s keyframes gave
    // identical output with 1 and 2 threads), and this is the command's
    // costliest step (sparse QR, then one solve per tangent coordinate).
    co.num_threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const auto start = std::chrono::steady_clock::now();
    ceres::Covariance covariance(co);
    std::vector<std::pair<const double*, const double*>> pairs;
    for (auto& b : blocks) pairs.emplace_back(b.data(), b.data());
    if (covariance.Compute(pairs, &problem)) {
      r.covariance_ok = true;
      Eigen::Matrix<double, 15, 15, Eigen::RowMajor> m;
      for (std::size_t i = 0; i < n; ++i) {
        covariance.GetCovarianceBlockInTangentSpace(blocks[i].data(), blocks[i].data(), m.data());
        r.keyframes[i].cov = m;
        if (!m.allFinite()) r.covariance_ok = false;
      }
      if (!r.covariance_ok) {
        for (Keyframe& k : r.keyframes) k.cov.setZero();
        r.covariance_message = "ceres::Covariance gave a covariance that is not finite";
      }
    } else {
      r.covariance_message = "ceres::Covariance failed: the problem's Jacobian is rank deficient";
    }
    r.covariance_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  } else if (options.covariance) {
    r.covariance_message = "not computed: the solve did not converge";
  }

  if (r.has_reference_bias && r.covariance_ok) {
    const int og = BlockOffset(labels, "bg"), oa = BlockOffset(labels, "ba");
    for (const Keyframe& k : r.keyframes) {
      const Vec3 dg = k.x.bg - k.ref_bg, da = k.x.ba - k.ref_ba;
      for (int a = 0; a < 3; ++a) {
        r.bias.rms_bg[a] += dg[a] * dg[a];
        r.bias.rms_ba[a] += da[a] * da[a];
        r.bias.within_3sigma_bg[a] +=
            std::abs(dg[a]) <= 3 * std::sqrt(k.cov(og + a, og + a)) ? 1 : 0;
        r.bias.within_3sigma_ba[a] +=
            std::abs(da[a]) <= 3 * std::sqrt(k.cov(oa + a, oa + a)) ? 1 : 0;
      }
    }
    const double count = static_cast<double>(n);
    r.bias.rms_bg = (r.bias.rms_bg / count).cwiseSqrt();
    r.bias.rms_ba = (r.bias.rms_ba / count).cwiseSqrt();
    r.bias.within_3sigma_bg /= count;
    r.bias.within_3sigma_ba /= count;
  }
  return r;
}

}  // namespace imuconv::optimize
