#include "trial.h"

#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "imuconv/so3.h"
#include "imuconv/window.h"
#include "normal.h"

namespace imuconv::experiment {
namespace {

/// Uniforms from mt19937_64's top 53 bits and normals by Box-Muller: the standard library's
/// distributions are implementation-defined, these are not (only libm's log, sin, cos).
class Random {
 public:
  explicit Random(std::uint64_t seed) : rng_(seed) {}
  double Uniform() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }  // [0, 1)
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  double Normal() {
    const double u1 = 1.0 - Uniform();  // (0, 1]
    const double u2 = Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  Vec3 Normal3(double sd) {
    const double x = Normal(), y = Normal(), z = Normal();
    return Vec3(sd * x, sd * y, sd * z);
  }

 private:
  std::mt19937_64 rng_;
};

/// One axis of a smooth signal: three sinusoids of amplitude up to amp/3 and frequency up to
/// fmax_hz, plus a constant offset of standard deviation `offset_sd`.
struct AxisSignal {
  double freq[3], phase[3], amp[3], offset;
  AxisSignal(Random& rng, double amp_max, double fmax_hz, double offset_sd) {
    for (int i = 0; i < 3; ++i) {
      freq[i] = rng.Uniform(0.05, fmax_hz);
      phase[i] = rng.Uniform(0.0, 2.0 * M_PI);
      amp[i] = rng.Uniform(0.2, 1.0) * amp_max / 3.0;
    }
    offset = offset_sd * rng.Normal();
  }
  double operator()(double t) const {
    double s = offset;
    for (int i = 0; i < 3; ++i) s += amp[i] * std::sin(2.0 * M_PI * freq[i] * t + phase[i]);
    return s;
  }
};

}  // namespace

Trial MakeTrial(std::uint64_t seed, std::uint64_t index, const TrialSpec& spec) {
  // SplitMix64 (montecarlo/normal.h, the same finaliser): unrelated seeds from (seed, index).
  Random rng(montecarlo::SplitMix64(montecarlo::SplitMix64(seed) + index));
  Trial trial;
  std::vector<AxisSignal> gyro, accel;
  for (int a = 0; a < 3; ++a) gyro.emplace_back(rng, 1.0, 2.0, 0.05);
  for (int a = 0; a < 3; ++a) accel.emplace_back(rng, 3.0, 2.0, 0.3);
  Vec3 g_body = rng.Normal3(1.0);
  g_body *= 9.81 / g_body.norm();  // roughly the reaction to gravity of a body at rest

  const auto knots = static_cast<std::size_t>(std::llround(spec.rate_hz * spec.duration_s)) + 1;
  trial.samples.resize(knots);
  for (std::size_t k = 0; k < knots; ++k) {
    ImuSample& s = trial.samples[k];
    s.t = static_cast<double>(k) / spec.rate_hz;
    for (int a = 0; a < 3; ++a) {
      s.gyro[a] = gyro[a](s.t);
      s.accel[a] = accel[a](s.t) + g_body[a];
    }
  }

  trial.noise.gyro_noise_density = std::pow(10.0, rng.Uniform(-3.5, -2.0));   // rad/s/sqrt(Hz)
  trial.noise.accel_noise_density = std::pow(10.0, rng.Uniform(-2.5, -1.0));  // m/s^2/sqrt(Hz)
  trial.noise.gyro_random_walk = std::pow(10.0, rng.Uniform(-5.5, -4.0));     // rad/s^2/sqrt(Hz)
  trial.noise.accel_random_walk = std::pow(10.0, rng.Uniform(-4.5, -3.0));    // m/s^3/sqrt(Hz)

  Eigen::Vector4d q(rng.Normal(), rng.Normal(), rng.Normal(), rng.Normal());  // w, x, y, z
  q.normalize();
  trial.x_s.R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
  trial.x_s.p = rng.Normal3(10.0);
  trial.x_s.v = rng.Normal3(2.0);
  trial.x_s.bg = rng.Normal3(0.01);
  trial.x_s.ba = rng.Normal3(0.1);

  // A random correlation matrix kept well conditioned (0.6 C + 0.4 I), scaled by the
  // standard deviations of each block [p, theta, v, bg, ba].
  Mat15 A;
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j) A(i, j) = rng.Normal();
  Mat15 C = A * A.transpose() / 15.0 + Mat15::Identity();
  const Vec15 inv_sd = C.diagonal().cwiseSqrt().cwiseInverse();
  C = 0.6 * inv_sd.asDiagonal() * C * inv_sd.asDiagonal() + 0.4 * Mat15::Identity();
  Vec15 sd;
  sd << Vec3::Constant(10.0), Vec3::Constant(std::sqrt(0.1)), Vec3::Constant(std::sqrt(10.0)),
      Vec3::Constant(0.01), Vec3::Constant(0.1);
  trial.cov_s_left = sd.asDiagonal() * C * sd.asDiagonal();
  trial.cov_s_left = 0.5 * (trial.cov_s_left + trial.cov_s_left.transpose()).eval();
  return trial;
}

std::vector<ImuSample> Subdivide(const std::vector<ImuSample>& samples, int factor) {
  if (factor <= 1 || samples.size() < 2) return samples;
  std::vector<ImuSample> out;
  out.reserve((samples.size() - 1) * static_cast<std::size_t>(factor) + 1);
  for (std::size_t k = 0; k + 1 < samples.size(); ++k)
    for (int j = 0; j < factor; ++j) {
      const double t = samples[k].t + (samples[k + 1].t - samples[k].t) * j / factor;
      out.push_back(j == 0 ? samples[k] : InterpolateSample(samples[k], samples[k + 1], t));
    }
  out.push_back(samples.back());
  return out;
}

}  // namespace imuconv::experiment
