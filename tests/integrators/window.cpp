// How the integrators read a SampleWindow: interpolated first and last knots are used like any
// other knot, the shortest window works, and every kind of bad input gives a Status error
// (never an exception, and the output is left untouched).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "integrator_cases.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;

// Linear interpolation written independently of InterpolateSample.
ImuSample Lerp(const ImuSample& a, const ImuSample& b, double t) {
  const double u = (t - a.t) / (b.t - a.t);
  ImuSample s;
  s.t = t;
  s.gyro = (1.0 - u) * a.gyro + u * b.gyro;
  s.accel = (1.0 - u) * a.accel + u * b.accel;
  return s;
}

TEST(IntegratorWindow, BetweenSamplesEqualsExplicitlyInterpolatedSamples) {
  const ImuCase c = LoadCase("jitter-0");  // non-uniform dt
  const auto& s = c.samples;
  const double t_s = s[50].t + 0.3 * (s[51].t - s[50].t),
               t_e = s[250].t + 0.8 * (s[251].t - s[250].t);
  const PropagationInput from_samples = MakeInput(c, t_s, t_e);
  ASSERT_EQ(from_samples.window.size(), 202u);  // t_s, samples 51..250, t_e

  std::vector<ImuSample> explicit_knots{Lerp(s[50], s[51], t_s)};
  explicit_knots.insert(explicit_knots.end(), s.begin() + 51, s.begin() + 251);
  explicit_knots.push_back(Lerp(s[250], s[251], t_e));
  PropagationInput from_knots = from_samples;
  ASSERT_TRUE(
      MakeWindow(explicit_knots.data(), explicit_knots.size(), t_s, t_e, from_knots.window).ok());
  ASSERT_EQ(from_knots.window.size(), explicit_knots.size());

  for (Integrator i : kIntegrators) {
    PropagationResult a, b;
    ASSERT_TRUE(PropagateKernel(i, from_samples, a).ok());
    ASSERT_TRUE(PropagateKernel(i, from_knots, b).ok());
    Vec15 d;
    LeftLocal(a.x_e, b.x_e, d);
    // The two interpolations differ by rounding (~1e-16 relative) in the end knots only.
    EXPECT_LT(d.cwiseAbs().maxCoeff(), 1e-12) << Name(i);
    EXPECT_LT(RelChange(b.Phi, a.Phi), 1e-12) << Name(i);
    EXPECT_LT(RelChange(b.cov, a.cov), 1e-12) << Name(i);
  }
}

// Wrongly treating the end knots (e.g. skipping them) would show here: the interval is one
// sample period and the result is compared with a single hand-computed step.
TEST(IntegratorWindow, TwoKnotWindowInsideOneSamplePeriod) {
  const ImuCase c = LoadCase("smooth-0");
  const auto& s = c.samples;
  const double t_s = s[10].t + 0.25 * (s[11].t - s[10].t),
               t_e = s[10].t + 0.75 * (s[11].t - s[10].t);
  const PropagationInput in = MakeInput(c, t_s, t_e);
  ASSERT_EQ(in.window.size(), 2u);
  PropagationResult euler;
  ASSERT_TRUE(PropagateKernel(Integrator::Euler, in, euler).ok());
  ImuState expected;
  kernels::EulerStep<false>(in.x_s, in.window[0].gyro, in.window[0].accel, t_e - t_s, in.gravity,
                            expected, nullptr);
  // One step by two code paths (the propagator's driver and EulerStep) that evaluate the same
  // formula but need not round alike: bit-for-bit agreement would be a coincidence (elsewhere
  // they differ by 1.1e-16). Each entry is a sum of a few rounded products, so they agree to
  // a few ulps of the largest term: 16 eps (3.6e-15) relative to max(1, |value|). Holding the
  // sample instead of the interpolated first knot moves v and R by 6e-6 and p by 8e-10
  // relative (measured), five or more orders above the bound.
  constexpr double kUlps = 16 * std::numeric_limits<double>::epsilon();
  auto near = [&](const auto& a, const auto& b) {
    return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
  };
  EXPECT_LE(near(euler.x_e.p, expected.p), kUlps)
      << euler.x_e.p.transpose() << " vs " << expected.p.transpose();
  EXPECT_LE(near(euler.x_e.v, expected.v), kUlps)
      << euler.x_e.v.transpose() << " vs " << expected.v.transpose();
  EXPECT_LE(near(euler.x_e.R, expected.R), kUlps) << euler.x_e.R << "\nvs\n" << expected.R;
  for (Integrator i : kIntegrators) {
    PropagationResult r;
    ASSERT_TRUE(PropagateKernel(i, in, r).ok()) << Name(i);
    EXPECT_TRUE(r.Phi.allFinite() && r.cov.allFinite()) << Name(i);
  }
}

// ---- bad input ------------------------------------------------------------------------

struct BadInput {
  std::string what;
  PropagationInput in;
};

std::vector<BadInput> BadInputs(const ImuCase& c, std::vector<ImuSample>& storage) {
  const double nan = std::numeric_limits<double>::quiet_NaN(),
               inf = std::numeric_limits<double>::infinity();
  const PropagationInput good = MakeInput(c, c.samples[0].t, c.samples[20].t);
  std::vector<BadInput> bad;
  auto add = [&](std::string what, auto&& change) {
    BadInput b{std::move(what), good};
    change(b.in);
    bad.push_back(std::move(b));
  };
  add("default window (both knots at t = 0)",
      [](PropagationInput& in) { in.window = SampleWindow(); });
  add("malformed window (end before begin)",
      [](PropagationInput& in) { std::swap(in.window.begin, in.window.end); });
  add("interior knots without samples", [](PropagationInput& in) { in.window.samples = nullptr; });
  add("last knot not after the first",
      [](PropagationInput& in) { in.window.last.t = in.window.first.t; });
  add("NaN time", [&](PropagationInput& in) { in.window.first.t = nan; });
  add("NaN gyro in the first knot", [&](PropagationInput& in) { in.window.first.gyro.y() = nan; });
  add("infinite accel in the last knot",
      [&](PropagationInput& in) { in.window.last.accel.z() = inf; });
  add("NaN rotation", [&](PropagationInput& in) { in.x_s.R(1, 2) = nan; });
  add("infinite velocity", [&](PropagationInput& in) { in.x_s.v.x() = -inf; });
  add("NaN bias", [&](PropagationInput& in) { in.x_s.ba.y() = nan; });
  add("NaN covariance", [&](PropagationInput& in) { in.cov_s(4, 7) = nan; });
  add("NaN gravity", [&](PropagationInput& in) { in.gravity.z() = nan; });
  add("negative noise density", [](PropagationInput& in) { in.noise.accel_noise_density = -1e-3; });
  add("NaN random walk", [&](PropagationInput& in) { in.noise.gyro_random_walk = nan; });
  // Interior samples out of order or repeated, and a non-finite interior sample.
  storage.assign(c.samples.begin(), c.samples.begin() + 21);
  storage[5].t = storage[4].t;
  storage[12].t = storage[11].t - 1e-3;
  storage[15].gyro.x() = nan;
  auto interior = [&](PropagationInput& in) { in.window.samples = storage.data(); };
  add("repeated time", [&](PropagationInput& in) {
    interior(in);
    in.window.end = 11;  // stops before the decreasing time and the NaN
  });
  add("decreasing time", [&](PropagationInput& in) {
    interior(in);
    in.window.begin = 6;  // starts after the repeated time
    in.window.first = storage[5];
    in.window.end = 14;
  });
  add("NaN interior gyro", [&](PropagationInput& in) {
    interior(in);
    in.window.begin = 13;
    in.window.first = storage[12];
  });
  return bad;
}

TEST(IntegratorWindow, BadInputGivesStatusErrorAndLeavesOutputAlone) {
  const ImuCase c = LoadCase("smooth-0");
  std::vector<ImuSample> storage;
  const std::vector<BadInput> bad = BadInputs(c, storage);
  for (const BadInput& b : bad) {
    for (Integrator i : kIntegrators) {
      PropagationResult out;
      out.x_e.p = Vec3(1, 2, 3);
      out.cov.setConstant(7.0);
      const Status st = PropagateKernel(i, b.in, out);
      EXPECT_FALSE(st.ok()) << Name(i) << ": " << b.what;
      EXPECT_FALSE(st.message().empty()) << Name(i) << ": " << b.what;
      EXPECT_EQ(out.x_e.p, Vec3(1, 2, 3)) << Name(i) << ": " << b.what;
      EXPECT_EQ(out.cov, Mat15::Constant(7.0)) << Name(i) << ": " << b.what;
    }
  }
  // The good input the bad ones derive from is accepted.
  for (Integrator i : kIntegrators) {
    PropagationResult out;
    EXPECT_TRUE(PropagateKernel(i, MakeInput(c, c.samples[0].t, c.samples[20].t), out).ok())
        << Name(i);
  }
}

TEST(IntegratorWindow, Rk4RejectsNonPositiveSubsteps) {
  const ImuCase c = LoadCase("smooth-0");
  PropagationResult out;
  EXPECT_FALSE(kernels::PropagateRk4(MakeInput(c, c.samples[0].t, c.samples[20].t), out, 0).ok());
}

// Through the plugins the same inputs come back as Status errors, and Registry::propagate turns
// them into imuconv::Error naming the propagator.
TEST(IntegratorWindow, BadInputThroughPluginsAndRegistry) {
  const ImuCase c = LoadCase("smooth-0");
  std::vector<ImuSample> storage;
  const std::vector<BadInput> bad = BadInputs(c, storage);
  for (Integrator i : kIntegrators) {
    const auto prop = Plugins().propagator(Name(i));
    for (const BadInput& b : bad) {
      PropagationResult out;
      const Status st = prop->propagate(b.in, out);
      EXPECT_FALSE(st.ok()) << Name(i) << ": " << b.what;
      try {
        (void)Plugins().propagate(Name(i), "left", b.in);  // expected to throw
        ADD_FAILURE() << "no exception: " << Name(i) << ": " << b.what;
      } catch (const imuconv::Error& e) {
        EXPECT_NE(std::string(e.what()).find(Name(i)), std::string::npos) << e.what();
      }
    }
  }
}

}  // namespace
