// The mean-only path (a plugin's optional increment_mean(), core/include/imuconv/
// increment_mean.h, which the core's kernels give through kernels/mean_only.h and
// plugin/kernel_plugin.h; what imuconv montecarlo's trials run) against the full path a
// method's preintegration takes (its plugin, through the bridge's Preintegrate): the same
// increment bit for bit, for every plugin that provides it; and what a plugin without it says.
// Whether a plugin provides it is declared in its system's own test file
// (IMUCONV_INCREMENT_MEAN, tests/support/increment_mean_facts.h, which checks each
// declaration); this file runs the propagators' (tests/preintegrators/mean_only.cpp the
// preintegrators') and tests the default a plugin of one's own gets.
//
// Bit for bit for every method, no tolerance: each is one kernel compiled once in imuconv_core,
// which the plugin and the mean-only path both call. euler and midpoint run the preintegration
// kernel's recursion (held input), manifold and tangent the same recursion with its covariance
// switched off; rk4's state-only mode is the same compiled function as the plugin's full run,
// whose state is the same IEEE operations in every output mode (core/src/kernels/rk4_window.h,
// "Instances"). Until rk4 was compiled in the core, its plugin and montecarlo each compiled
// their own copy of the header-only kernel, and this test had to allow them 1e-13 apart.
#include <gtest/gtest.h>

#include <string>

#include "imuconv/increment_mean.h"
#include "increment_mean_facts.h"
#include "integrator_cases.h"

namespace imuconv::test {
namespace {

TEST(MeanOnly, EveryBuiltInPropagatorGivesWhatItDeclares) {
  CheckDeclaredIncrementMeans<PluginKind::Propagator>(
      "the propagator's own test file in tests/integrators/");
}

// A plugin that overrides nothing optional says "not provided" (the base classes' default,
// which montecarlo answers with the full path), and writes the identity rather than leave
// `delta` as it was.
TEST(MeanOnly, APluginWithoutItSaysNotProvided) {
  const ImuCase c = LoadCase("smooth-0");
  SampleWindow w;
  ASSERT_TRUE(MakeWindow(c.samples.data(), 20, c.samples.front().t, c.samples[19].t, w).ok());
  PreintegrationInput in;
  in.noise = c.noise;
  in.window = w;
  PreintIncrement stale;
  stale.dp = Vec3(1.0, 2.0, 3.0);
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
