// The windows of imuconv nees, their errors and statistics (nees.h).
#include "nees.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <numeric>

#include "imuconv/chi_square.h"
#include "imuconv/did_you_mean.h"
#include "imuconv/pipeline/timing.h"
#include "imuconv/printable.h"
#include "imuconv/window.h"
#include "order_statistics.h"
#include "split_factors.h"

namespace imuconv::nees {

ChiSquareReference ChiSquare9() {
  ChiSquareReference r;
  r.median = ChiSquareQuantileExact(kDof, 0.5);
  r.lower = ChiSquareQuantileExact(kDof, (1.0 - kConfidence) / 2.0);
  r.upper = ChiSquareQuantileExact(kDof, (1.0 + kConfidence) / 2.0);
  return r;
}

namespace {

std::string Seconds(double s, int digits = 9) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g s", digits, s);
  return buf;
}

// A count estimated in doubles, whole below 1e15 (any real count), else in three digits.
std::string WindowCount(double n) {
  char buf[32];
  if (n < 1e15)
    std::snprintf(buf, sizeof buf, "%.0f", std::floor(n));
  else
    std::snprintf(buf, sizeof buf, "%.3g", n);
  return buf;
}

// 0 when [t_s, t_e] holds an IMU sample, its ends included within kSameInstant (the rule of
// docs/timing.md, "Intervals holding no sample", as the run's "check times" stage applies it);
// else the time between the two samples it lies between (infinite past either end).
double SpacingAroundEmptyWindow(const std::vector<ImuSample>& samples, double t_s, double t_e) {
  const auto first =
      std::lower_bound(samples.begin(), samples.end(), t_s - kSameInstant,
                       [](const ImuSample& sample, double t) { return sample.t < t; });
  if (first != samples.end() && first->t <= t_e + kSameInstant) return 0.0;
  if (first == samples.begin() || first == samples.end())
    return std::numeric_limits<double>::infinity();
  return first->t - std::prev(first)->t;
}

// Whether [t_s, t_e] reaches into a gap of the samples, the open interval between two samples
// listed in `gaps` (each i: samples i and i + 1 are a gap apart), beyond kSameInstant.
bool ReachesIntoGap(const std::vector<ImuSample>& samples, const std::vector<std::size_t>& gaps,
                    double t_s, double t_e) {
  // The first gap ending after t_s (the gaps' ends increase with i).
  const auto gap =
      std::lower_bound(gaps.begin(), gaps.end(), t_s + kSameInstant,
                       [&samples](std::size_t i, double t) { return samples[i + 1].t <= t; });
  return gap != gaps.end() && samples[*gap].t < t_e - kSameInstant;
}

// The [p, theta, v] blocks of a 15-dim error and covariance, by label offsets.
void PickBlocks(const Vec15& d, const Mat15& cov, const int (&offsets)[3], Vec9& e, Mat9& P) {
  for (int i = 0; i < 3; ++i) {
    e.segment<3>(3 * i) = d.segment<3>(offsets[i]);
    for (int j = 0; j < 3; ++j)
      P.block<3, 3>(3 * i, 3 * j) = cov.block<3, 3>(offsets[i], offsets[j]);
  }
}

// One window [t_s, t_e]: its NEES under the declared densities, its error and sigmas, and the
// covariance's gyro and accelerometer parts (each propagated with that sensor's densities alone;
// the end state is the same in all three runs, the noise does not move the mean).
double Window(const Registry& reg, const pipeline::ImuData& imu, const pipeline::GroundTruth& gt,
              const Options& options, const int (&offsets)[3], double t_s, double t_e, Vec9& error,
              Vec9& sigma, Mat9& cov_gyro, Mat9& cov_accel) {
  const auto x_s = gt.at(t_s), x_gt = gt.at(t_e);
  if (!x_s || !x_gt)
    throw Error("window [" + Seconds(t_s) + ", " + Seconds(t_e) + "] leaves the ground truth");
  PropagationInput in;
  in.x_s = *x_s;  // the ground truth's biases included: the error measures the noise model only
  in.cov_s = Mat15::Zero();
  in.noise = options.noise;
  in.gravity = options.gravity;
  const Status st = MakeWindow(imu.samples.data(), imu.samples.size(), t_s, t_e, in.window);
  if (!st.ok()) throw Error("window [" + Seconds(t_s) + ", " + Seconds(t_e) + "]: " + st.message());
  const PropagationResult out = reg.propagate(options.method, options.convention, in);
  Vec15 d;
  reg.state_convention(options.convention)->local(*x_gt, out.x_e, d);
  Mat9 P;
  PickBlocks(d, out.cov, offsets, error, P);
  const Eigen::LLT<Mat9> llt(0.5 * (P + P.transpose()));
  if (llt.info() != Eigen::Success)
    throw Error("window [" + Seconds(t_s) + ", " + Seconds(t_e) +
                "]: the propagated [p, theta, v] covariance is not positive definite");
  sigma = P.diagonal().cwiseSqrt();
  Vec9 unused;
  in.noise = ImuNoise{options.noise.gyro_noise_density, 0.0, options.noise.gyro_random_walk, 0.0};
  PickBlocks(d, reg.propagate(options.method, options.convention, in).cov, offsets, unused,
             cov_gyro);
  in.noise = ImuNoise{0.0, options.noise.accel_noise_density, 0.0, options.noise.accel_random_walk};
  PickBlocks(d, reg.propagate(options.method, options.convention, in).cov, offsets, unused,
             cov_accel);
  return llt.matrixL().solve(error).squaredNorm();
}

}  // namespace

Result RunNees(const Registry& reg, const pipeline::ImuData& imu, const pipeline::GroundTruth& gt,
               const Options& options) {
  if (!reg.has(PluginKind::Propagator, options.method)) {
    std::string known;
    for (const auto& id : reg.ids(PluginKind::Propagator))
      known += (known.empty() ? "" : ", ") + id;
    const std::string hint =
        reg.has(PluginKind::Preintegrator, options.method)
            ? " (it is a preintegrator; nees propagates states from the ground truth)"
            : "";
    throw Error("--method: unknown propagator " + Printable(options.method) + hint +
                DidYouMean(options.method, reg.ids(PluginKind::Propagator)) + "; known: " + known);
  }
  const ImuNoise& q = options.noise;
  if (q.gyro_noise_density == 0 && q.accel_noise_density == 0 && q.gyro_random_walk == 0 &&
      q.accel_random_walk == 0)
    throw Error(
        "--noise: all four densities are zero; the propagated covariance would be zero and NEES "
        "undefined");
  const BlockLabels labels = reg.state_convention(options.convention)->labels();
  const int offsets[3] = {BlockOffset(labels, "p"), BlockOffset(labels, "theta"),
                          BlockOffset(labels, "v")};

  Result r;
  r.method = options.method;
  r.convention = options.convention;
  r.noise = options.noise;
  r.chi2 = ChiSquare9();
  if (imu.samples.size() < 2 || gt.t.size() < 2)
    throw Error("fewer than two IMU samples or ground-truth rows");
  r.t_begin = std::max(imu.samples.front().t, gt.t.front());
  r.t_end = std::min(imu.samples.back().t, gt.t.back());
  const double span = r.t_end - r.t_begin;
  // Times are relative seconds of ~1e2 magnitude: 1 ns absorbs their rounding (the data's
  // stamps are integer nanoseconds), so a window ending exactly at the last row still counts.
  constexpr double kTimeSlack = 1e-9;
  std::vector<double> sample_times(imu.samples.size());
  for (std::size_t i = 0; i < imu.samples.size(); ++i) sample_times[i] = imu.samples[i].t;
  const double period = pipeline::MedianPeriod(sample_times);
  // A gap: two samples more than the readers' max_gap_factor (10) median periods apart
  // (docs/timing.md), which only data read with allow_gaps has.
  const double gap_limit = pipeline::TimingPolicy{}.max_gap_factor * period;
  std::vector<std::size_t> gaps;
  for (std::size_t i = 0; i + 1 < sample_times.size(); ++i)
    if (sample_times[i + 1] - sample_times[i] > gap_limit) gaps.push_back(i);
  // Every length checked, and the windows of all of them counted, before any is propagated.
  double total_windows = 0.0;
  for (const double length : options.window_lengths) {
    if (!(length > 0) || !std::isfinite(length))
      throw Error("--windows: " + Seconds(length) + " is not a positive length");
    if (length > span + kTimeSlack)
      throw Error("--windows: " + Seconds(length) + " is longer than the " + Seconds(span) +
                  " the IMU data and the ground truth share");
    // A window shorter than the sample period lies between two samples (or holds one): it is
    // interpolation, not IMU data, and such a length is almost always one in the wrong unit.
    // The rule of every interval (docs/timing.md), applied to the length once.
    if (length < period - kTimeSlack)
      throw Error("--windows: " + Seconds(length) + " is shorter than the IMU's sample period, " +
                  Seconds(period, 6) + " (median): its windows, the first [" + Seconds(r.t_begin) +
                  ", " + Seconds(r.t_begin + length) +
                  "], would lie between two samples, interpolation only (a length in the wrong "
                  "unit?)");
    const double stride = options.stride > 0 ? options.stride : length;
    total_windows += (span - length) / stride + 1;
  }
  // The bound is on all the lengths together: applied to each length alone, three lengths at a
  // stride typo (2e-5 s) were 3 million windows and ran out of 4 GB. Each window keeps some
  // 1.6 KB (its two 9x9 covariance parts, error and sigma); measured on the EuRoC slice, 100 000
  // windows peak at 170 MB, and at 1.7 GB with --json (its document is built whole, every
  // window's matrices as JSON values). kMaxWindows, the number nees always had, is kept (a run
  // that worked stays allowed). A stride far below the sample period only repeats windows.
  if (total_windows > static_cast<double>(kMaxWindows))
    throw Error("--windows, --stride: " + std::to_string(options.window_lengths.size()) +
                " window length(s) at a stride of " +
                (options.stride > 0 ? Seconds(options.stride) : std::string("their own length")) +
                " make " + WindowCount(total_windows) + " windows, more than " +
                std::to_string(kMaxWindows) + " in all (a larger --stride, or fewer lengths)");
  for (const double length : options.window_lengths) {
    WindowLengthResult w;
    w.length = length;
    w.stride = options.stride > 0 ? options.stride : length;
    for (std::size_t i = 0;; ++i) {
      // Starts by multiplication, not accumulation, so they carry no drift.
      const double t_s = r.t_begin + static_cast<double>(i) * w.stride;
      double t_e = t_s + length;
      if (t_e > r.t_end + kTimeSlack) break;
      t_e = std::min(t_e, r.t_end);
      // A window holding no sample between two ordinary samples: the length is too short for
      // the samples' jitter, refused. One between the two samples of a gap lies in the gap.
      const double spacing = SpacingAroundEmptyWindow(imu.samples, t_s, t_e);
      if (spacing > 0 && !(spacing > gap_limit))
        throw Error("--windows: the window [" + Seconds(t_s) + ", " + Seconds(t_e) + "] of " +
                    Seconds(length) + " holds no IMU sample: it lies between two samples " +
                    Seconds(spacing, 6) + " apart (the median period is " + Seconds(period, 6) +
                    "); every window must hold one (a longer window)");
      // A window reaching into a gap (lying in it, or holding samples on one side of it) would
      // be propagated over the gap by interpolation and compared with a ground truth
      // interpolated across it: skipped and counted, never fitted.
      if (ReachesIntoGap(imu.samples, gaps, t_s, t_e)) {
        if (w.skipped_in_gap == 0) w.first_skipped = t_s;
        ++w.skipped_in_gap;
        continue;
      }
      w.t_start.push_back(t_s);
      Vec9 e, sigma;
      Mat9 cov_gyro, cov_accel;
      w.nees.push_back(
          Window(reg, imu, gt, options, offsets, t_s, t_e, e, sigma, cov_gyro, cov_accel));
      w.error.push_back(e);
      w.sigma.push_back(sigma);
      w.cov_gyro.push_back(cov_gyro);
      w.cov_accel.push_back(cov_accel);
    }
    if (w.nees.empty())
      throw Error("--windows: all " + std::to_string(w.skipped_in_gap) + " windows of " +
                  Seconds(length) + " reach into a gap of the data, the first [" +
                  Seconds(w.first_skipped) + ", " + Seconds(w.first_skipped + length) +
                  "]: nothing to fit (a shorter window)");
    w.median = SampleMedian(w.nees);
    w.mean =
        std::accumulate(w.nees.begin(), w.nees.end(), 0.0) / static_cast<double>(w.nees.size());
    w.p95 = SampleQuantile(w.nees, 0.95);
    std::size_t inside = 0;
    for (const double v : w.nees) inside += (v >= r.chi2.lower && v <= r.chi2.upper) ? 1 : 0;
    w.fraction_inside = static_cast<double>(inside) / static_cast<double>(w.nees.size());
    w.factor = std::sqrt(w.median / r.chi2.median);
    w.factor_gyro = FitGyroFactor(w.error, w.cov_gyro);
    w.factor_accel = FitAccelFactor(w.error, w.cov_gyro, w.cov_accel, w.factor_gyro);
    if (std::isfinite(w.factor_gyro) && std::isfinite(w.factor_accel))
      w.components =
          ComponentStatisticsOf(w.error, w.cov_gyro, w.cov_accel, w.factor_gyro, w.factor_accel);
    r.windows.push_back(std::move(w));
  }
  return r;
}

}  // namespace imuconv::nees
