// `orb_slam3`: ORB-SLAM3's IMU preintegration (IMU::Preintegrated fed by
// Tracking::PreintegrateIMU), in single precision as the original computes it: each step
// integrates the mean of two consecutive samples over their float time difference
// (kernels/orb_slam3.h has the scheme). The numbers are the kernel's floats widened to double,
// bit for bit ORB-SLAM3's own on x86-64 (tests/reference/orb_slam3_plugin.cpp).
//
// Noise, as ORB-SLAM3's code reads it. Its yaml keys IMU.NoiseGyro, IMU.NoiseAcc,
// IMU.GyroWalk and IMU.AccWalk hold continuous densities, the numbers this plugin is given, and
// the Tracking constructor makes IMU::Calib(Ng sqrt f, Na sqrt f, Ngw / sqrt f, Naw / sqrt f)
// with f = IMU.Frequency; Calib squares them into the per-sample variances sigma^2 f and the
// per-step walk variances sigma_w^2 / f. So the white noise adds sigma^2 f dt^2 per step
// (sigma^2 dt only where dt = 1/f) and the walk sigma_w^2 / f per step whatever the step's dt.
// f is the one number a user's yaml has that a window does not carry: here it is the nominal
// rate of the window, 1/median step rounded to whole hertz (IMU.Frequency is the sensor's
// nominal rate, a whole number of hertz for the IMUs ORB-SLAM3 ships settings for: 200 for
// EuRoC and TUM-VI); the median ignores the short first and last steps of a window cut
// between samples, and on sampling jitter of +-40 % (the reference jitter cases: median
// rate 200.4 and 200.3 Hz) it still gives 200. Below 1 Hz the rate is used unrounded. There is
// no `orb_slam3_as_configured`: the four numbers of ORB-SLAM3's yaml are these densities, so
// such a plugin would take the same numbers and compute the same thing (docs/orb-slam3.md).
//
// Output: the increment (dR, dV, dP; the bias entries zero) and its duration, dT, the float
// sum of the float steps that ORB-SLAM3's prediction and EdgeInertial use (10.000181 s for
// 2000 steps of 5 ms, not 10 s); the covariance C and the bias Jacobian [[JRg, 0], [JVg, JVa],
// [JPg, JPa]] in the `orb_slam3` increment convention.
#include <algorithm>
#include <cmath>
#include <vector>

#include "imuconv/kernels/orb_slam3.h"
#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {

using namespace imuconv;
namespace k = imuconv::kernels;

/// IMU.Frequency for a window: its nominal rate (the file comment says why this way).
double NominalRate(const SampleWindow& w) {
  std::vector<double> steps;
  steps.reserve(w.size() - 1);
  for (std::size_t j = 0; j + 1 < w.size(); ++j) steps.push_back(w[j + 1].t - w[j].t);
  auto mid = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), mid, steps.end());
  const double rate = 1.0 / *mid;
  return rate >= 1.0 ? std::round(rate) : rate;
}

struct OrbSlam3Scheme {
  static constexpr const char* kCovConvention = "orb_slam3";
  static constexpr const char* kJacobianConvention = "orb_slam3";
  // Each step integrates the mean of its two samples (each sample weighed over half of each
  // step beside it); the bias constant over the interval, its walk only in C's bias blocks.
  static constexpr NoiseSimulation kNoiseSimulation{
      SampleCells::kCentered, NoiseReading::kWalkInIncrementOnly, /*simulable=*/true,
      ", as ORB-SLAM3's preintegration assumes (its bias walk is weighted by separate edges; "
      "docs/orb-slam3.md)"};
  Status operator()(const PreintegrationInput& in, Preintegrated& out) const {
    const SampleWindow& w = in.window;
    if (w.size() < 2) return Status::Error("ORB-SLAM3 preintegration: the window has no step");
    std::vector<ImuSample> samples;
    samples.reserve(w.size());
    for (std::size_t j = 0; j < w.size(); ++j) samples.push_back(w[j]);
    std::vector<k::OrbSlam3Step> steps;
    if (Status st = k::OrbSlam3Steps(samples, steps); !st.ok()) return st;
    const double rate = NominalRate(w);
    if (!std::isfinite(rate) || !(rate > 0.0))
      return Status::Error("ORB-SLAM3 preintegration: the window's nominal rate is not finite");
    const k::OrbSlam3Bias b{in.bg.cast<float>(), in.ba.cast<float>()};
    if (!b.bg.allFinite() || !b.ba.allFinite())
      return Status::Error("ORB-SLAM3 preintegration: the bias estimate is not finite in float");
    const k::OrbSlam3Preintegrated p =
        k::PreintegrateOrbSlam3(steps, k::OrbSlam3CalibFromDensities(in.noise, rate), b);

    out.dt = p.dT;
    out.delta.dR = p.dR.cast<double>();
    out.delta.dv = p.dV.cast<double>();
    out.delta.dp = p.dP.cast<double>();
    out.delta.dbg.setZero();
    out.delta.dba.setZero();
    out.bg_hat = in.bg;
    out.ba_hat = in.ba;
    out.cov = p.C.cast<double>();  // already [theta, v, p, bg, ba]
    out.J_bias.setZero();          // rows [theta; v; p], columns [bg, ba]
    out.J_bias.block<3, 3>(0, 0) = p.JRg.cast<double>();
    out.J_bias.block<3, 3>(3, 0) = p.JVg.cast<double>();
    out.J_bias.block<3, 3>(3, 3) = p.JVa.cast<double>();
    out.J_bias.block<3, 3>(6, 0) = p.JPg.cast<double>();
    out.J_bias.block<3, 3>(6, 3) = p.JPa.cast<double>();
    if (!out.cov.allFinite() || !out.J_bias.allFinite() || !out.delta.dp.allFinite() ||
        !out.delta.dv.allFinite() || !out.delta.dR.allFinite())
      return Status::Error(
          "ORB-SLAM3 preintegration: the result overflows single precision (the samples or the "
          "noise are too large for float)");
    return Status::Ok();
  }
};

}  // namespace

IMUCONV_PLUGIN(Preintegrator, imuconv::plugin::KernelPreintegrator<OrbSlam3Scheme>, "orb_slam3",
               "1.0.0",
               "ORB-SLAM3 IMU::Preintegrated in float, consecutive samples averaged; densities "
               "scaled by the nominal rate as its Tracking does")
