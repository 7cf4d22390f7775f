// The mean-only path (a plugin's optional increment_mean(), core/include/imuconv/
// increment_mean.h, which the core's kernels give through kernels/mean_only.h and
// plugin/kernel_plugin.h; what imuconv montecarlo's trials run) against the full path a
// method's preintegration takes (its plugin, through the bridge's Preintegrate): the same
// increment bit for bit, for every plugin that provides it; and what a plugin without it says.
//
// Bit for bit for every method, no tolerance: each is one kernel compiled once in imuconv_core,
// which the plugin and the mean-only path both call. euler and midpoint run the preintegration
// kernel's recursion (held input), manifold and tangent the same recursion with its covariance
// switched off; rk4's state-only mode is the same compiled function as the plugin's full run,
// whose state is the same IEEE operations in every output mode (core/src/kernels/rk4_window.h,
// "Instances"). Until rk4 was compiled in the core, its plugin and montecarlo each compiled
// their own copy of the header-only kernel, and this test had to allow them 1e-13 apart.
// The inputs are the reference cases' samples as they are, at a bias estimate, and with the
// kind of noise montecarlo adds (so the SIMD recursion sees unrounded, irregular values), over
// the whole case and a short window.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "imuconv/bridge.h"
#include "imuconv/increment_mean.h"
#include "integrator_cases.h"

namespace imuconv::test {
namespace {

struct Served {
  const char* id;
  PluginKind kind;
};

// The plugins whose kernel has a mean-only function (kernels/mean_only.h).
constexpr Served kServed[] = {
    {"euler", PluginKind::Propagator},      {"midpoint", PluginKind::Propagator},
    {"rk4", PluginKind::Propagator},        {"manifold", PluginKind::Preintegrator},
    {"tangent", PluginKind::Preintegrator},
};

// The plugin's increment_mean(), as montecarlo calls it.
Status PluginMean(const Registry& reg, const Served& m, const SampleWindow& w, const Vec3& bg,
                  const Vec3& ba, const ImuNoise& noise, PreintIncrement& mean) {
  PreintegrationInput in;
  in.bg = bg;
  in.ba = ba;
  in.noise = noise;
  in.window = w;
  return m.kind == PluginKind::Propagator ? reg.propagator(m.id)->increment_mean(in, mean)
                                          : reg.preintegrator(m.id)->increment_mean(in, mean);
}

// Bitwise equality of two matrices (EXPECT_EQ on Eigen compares values, which would let
// -0 == +0 through; that difference is harmless but is not "the same arithmetic", so the
// bytes are compared, then the values are printed on failure).
template <class A>
bool SameBits(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<A>& b) {
  return std::memcmp(a.derived().data(), b.derived().data(), sizeof(double) * a.size()) == 0;
}

bool SameIncrement(const PreintIncrement& a, const PreintIncrement& b) {
  return SameBits(a.dR, b.dR) && SameBits(a.dp, b.dp) && SameBits(a.dv, b.dv);
}

// Largest entry difference relative to the block's size (dR's entries are O(1)).
double RelativeDifference(const PreintIncrement& a, const PreintIncrement& b) {
  return std::max({(a.dR - b.dR).cwiseAbs().maxCoeff(),
                   (a.dp - b.dp).norm() / std::max(a.dp.norm(), 1e-300),
                   (a.dv - b.dv).norm() / std::max(a.dv.norm(), 1e-300)});
}

std::vector<ImuSample> Noisy(std::vector<ImuSample> s) {
  for (ImuSample& z : s) {
    z.gyro += RandVec(3e-3);
    z.accel += RandVec(3e-2);
  }
  return s;
}

TEST(MeanOnly, SameIncrementAsTheFullPathBitForBit) {
  const Registry& reg = Plugins();
  const Vec3 bg(2e-3, -1e-3, 4e-4), ba(0.03, -0.02, 0.01);
  int compared = 0;
  for (const Served& m : kServed) {
    const PreintegrationMethod method = ResolvePreintegrationMethod(reg, m.kind, m.id);
    for (const char* name : {"smooth-0", "aggressive-0", "jitter-0", "static-0"}) {
      const ImuCase c = LoadCase(name);
      for (const auto& samples : {c.samples, Noisy(c.samples)}) {
        for (double length : {1e9, 0.5}) {  // the whole case, and its first half second
          const double t_e = std::min(samples.back().t, samples.front().t + length);
          SampleWindow w;
          ASSERT_TRUE(MakeWindow(samples.data(), samples.size(), samples.front().t, t_e, w).ok());
          const Preintegrated full = Preintegrate(reg, method, w, bg, ba, c.noise);
          PreintIncrement mean;
          const Status st = PluginMean(reg, m, w, bg, ba, c.noise, mean);
          ASSERT_TRUE(st.ok()) << st.message();
          const std::string what = std::string(m.id) + " on " + name;
          EXPECT_TRUE(SameIncrement(full.delta, mean))
              << what << " (largest relative difference " << RelativeDifference(full.delta, mean)
              << ")\nfull dR\n"
              << full.delta.dR << "\nmean dR\n"
              << mean.dR << "\ndp " << full.delta.dp.transpose() << " vs " << mean.dp.transpose();
          EXPECT_EQ(mean.dbg, Vec3::Zero());
          EXPECT_EQ(mean.dba, Vec3::Zero());
          ++compared;
        }
      }
    }
  }
  EXPECT_EQ(compared, 5 * 4 * 2 * 2);
}

// Bad input is refused with the full path's message, not integrated.
TEST(MeanOnly, RefusesWhatTheFullPathRefuses) {
  const ImuCase c = LoadCase("smooth-0");
  std::vector<ImuSample> s(c.samples.begin(), c.samples.begin() + 10);
  s[4].gyro.x() = std::nan("");
  SampleWindow w;
  ASSERT_TRUE(MakeWindow(s.data(), s.size(), s.front().t, s.back().t, w).ok());
  for (const Served& m : kServed) {
    PreintIncrement mean;
    const Status st = PluginMean(Plugins(), m, w, Vec3::Zero(), Vec3::Zero(), c.noise, mean);
    EXPECT_FALSE(st.ok()) << m.id;
    EXPECT_NE(st.message().find("not finite"), std::string::npos) << m.id << ": " << st.message();
  }
}

// A plugin without the capability says "not provided" (the base classes' default, which
// montecarlo answers with the full path), and writes the identity rather than leave `delta`
// as it was: the built-in plugins whose kernel has no mean-only function, and a plugin that
// overrides nothing optional.
TEST(MeanOnly, APluginWithoutItSaysNotProvided) {
  const ImuCase c = LoadCase("smooth-0");
  SampleWindow w;
  ASSERT_TRUE(MakeWindow(c.samples.data(), 20, c.samples.front().t, c.samples[19].t, w).ok());
  PreintegrationInput in;
  in.noise = c.noise;
  in.window = w;
  PreintIncrement stale;
  stale.dp = Vec3(1.0, 2.0, 3.0);
  for (const char* id : {"openvins_rk4", "openvins_discrete", "openvins_analytical"}) {
    PreintIncrement mean = stale;
    const Status st = Plugins().propagator(id)->increment_mean(in, mean);
    EXPECT_TRUE(IsIncrementMeanNotProvided(st)) << id << ": " << st.message();
    EXPECT_EQ(mean.dp, Vec3::Zero()) << id;
  }
  for (const char* id : {"basalt", "basalt_as_configured", "basalt_forward_zoh", "vins_fusion",
                         "vins_fusion_as_configured"}) {
    PreintIncrement mean = stale;
    const Status st = Plugins().preintegrator(id)->increment_mean(in, mean);
    EXPECT_TRUE(IsIncrementMeanNotProvided(st)) << id << ": " << st.message();
    EXPECT_EQ(mean.dp, Vec3::Zero()) << id;
  }
  struct Bare final : Propagator {
    const char* id() const noexcept override { return "bare"; }
    const char* native_convention() const noexcept override { return "left"; }
    Status propagate(const PropagationInput&, PropagationResult&) const noexcept override {
      return Status::Ok();
    }
  } bare;
  PreintIncrement mean = stale;
  EXPECT_TRUE(IsIncrementMeanNotProvided(bare.increment_mean(in, mean)));
  EXPECT_EQ(mean.dp, Vec3::Zero());
  // And the default simulation facts: forward cells, continuous densities, simulable.
  const NoiseSimulation sim = bare.noise_simulation();
  EXPECT_EQ(sim.cells, SampleCells::kForward);
  EXPECT_EQ(sim.reading, NoiseReading::kContinuous);
  EXPECT_TRUE(sim.simulable);
  EXPECT_STREQ(sim.note, "");
  // A failure is not "not provided": the served plugins' bad-input message is not the sentinel.
  EXPECT_FALSE(IsIncrementMeanNotProvided(Status::Error("euler: not finite")));
  EXPECT_FALSE(IsIncrementMeanNotProvided(Status::Ok()));
}

}  // namespace
}  // namespace imuconv::test
