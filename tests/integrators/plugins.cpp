// The three integrator plugins through the registry: they load, declare `left` as their native
// convention, give what their kernels give, and Registry::propagate(id, "left", in) passes
// through unchanged.
#include <gtest/gtest.h>

#include <array>
#include <iostream>
#include <string>
#include <vector>

#include "integrator_cases.h"
#include "scheme_fact_declarations.h"

namespace {

// What each of the three says of its noise and mean (scheme_fact_declarations.h;
// docs/montecarlo.md): euler holds each sample over the step it starts; midpoint averages a
// step's two ends and rk4 interpolates linearly between knots, so each sample weighs half of
// each step beside it. All three give the mean alone (kernels/mean_only.h;
// tests/integrators/mean_only.cpp).
IMUCONV_SCHEME_FACTS(Propagator, euler, kForward, kContinuous, true, kProvided);
IMUCONV_SCHEME_FACTS(Propagator, midpoint, kCentered, kContinuous, true, kProvided);
IMUCONV_SCHEME_FACTS(Propagator, rk4, kCentered, kContinuous, true, kProvided);

using namespace imuconv;
using namespace imuconv::test;

PropagationInput SomeInput(const ImuCase& c) {
  // 2 s between samples on a jittered case: interpolated end knots and non-uniform steps.
  const double t_s = c.samples[30].t + 0.4 * (c.samples[31].t - c.samples[30].t);
  return MakeInput(c, t_s, t_s + 2.0);
}

class IntegratorPlugin : public ::testing::TestWithParam<Integrator> {};

TEST_P(IntegratorPlugin, LoadsWithLeftAsNativeConvention) {
  const char* id = Name(GetParam());
  ASSERT_TRUE(Plugins().has(PluginKind::Propagator, id)) << id;
  const auto prop = Plugins().propagator(id);
  EXPECT_STREQ(prop->id(), id);
  EXPECT_STREQ(prop->native_convention(), "left");
  const PluginInfo& info = Plugins().info(PluginKind::Propagator, id);
  EXPECT_EQ(info.native_convention, "left");
  EXPECT_NE(info.file.find(std::string("imuconv_plugin_integrators_") + id), std::string::npos)
      << info.file;
}

TEST_P(IntegratorPlugin, GivesWhatItsKernelGives) {
  const ImuCase c = LoadCase("jitter-1");
  const PropagationInput in = SomeInput(c);
  PropagationResult from_plugin, from_kernel;
  const Status st = Plugins().propagator(Name(GetParam()))->propagate(in, from_plugin);
  ASSERT_TRUE(st.ok()) << st.message();
  ASSERT_TRUE(PropagateKernel(GetParam(), in, from_kernel).ok());
  // The same header compiled into two binaries; only code generation could differ (rounding).
  Vec15 d;
  LeftLocal(from_kernel.x_e, from_plugin.x_e, d);
  EXPECT_LT(d.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(RelChange(from_plugin.Phi, from_kernel.Phi), 1e-12);
  EXPECT_LT(RelChange(from_plugin.cov, from_kernel.cov), 1e-12);
}

TEST_P(IntegratorPlugin, RegistryPropagateInNativeConventionIsThePluginResult) {
  const ImuCase c = LoadCase("jitter-1");
  const PropagationInput in = SomeInput(c);
  PropagationResult direct;
  ASSERT_TRUE(Plugins().propagator(Name(GetParam()))->propagate(in, direct).ok());
  const PropagationResult via_registry = Plugins().propagate(Name(GetParam()), "left", in);
  // No conversion happens for the native convention: bitwise equal.
  EXPECT_EQ(via_registry.x_e.R, direct.x_e.R);
  EXPECT_EQ(via_registry.x_e.p, direct.x_e.p);
  EXPECT_EQ(via_registry.x_e.v, direct.x_e.v);
  EXPECT_EQ(via_registry.Phi, direct.Phi);
  EXPECT_EQ(via_registry.cov, direct.cov);
}

INSTANTIATE_TEST_SUITE_P(Integrators, IntegratorPlugin, ::testing::ValuesIn(kIntegrators),
                         [](const ::testing::TestParamInfo<Integrator>& info) {
                           return std::string(Name(info.param));
                         });

// The three schemes differ only in discretisation. euler and midpoint both rotate the specific
// force with the rotation at the start of the step, so both are first order: over 2 s at
// 200 Hz they stay within ~dt |w| ~ 5e-3 (relative) of rk4, and shrink with the step.
TEST(IntegratorPlugins, SchemesAgreeToTheirOrder) {
  const ImuCase c = LoadCase("smooth-1");
  auto differences_to_rk4 = [&](const std::vector<ImuSample>& samples) {
    ImuCase sub = c;
    sub.samples = samples;
    const PropagationInput in = MakeInput(sub, c.samples[40].t, c.samples[440].t);
    PropagationResult euler, midpoint, rk4;
    EXPECT_TRUE(Plugins().propagator("euler")->propagate(in, euler).ok());
    EXPECT_TRUE(Plugins().propagator("midpoint")->propagate(in, midpoint).ok());
    EXPECT_TRUE(Plugins().propagator("rk4")->propagate(in, rk4).ok());
    return std::array<double, 4>{RelChange(euler.Phi, rk4.Phi), RelChange(midpoint.Phi, rk4.Phi),
                                 RelChange(euler.cov, rk4.cov), RelChange(midpoint.cov, rk4.cov)};
  };
  std::vector<ImuSample> every_other;  // 100 Hz
  for (std::size_t k = 0; k < c.samples.size(); k += 2) every_other.push_back(c.samples[k]);
  const auto at_200 = differences_to_rk4(c.samples), at_100 = differences_to_rk4(every_other);
  const char* what[] = {"euler Phi", "midpoint Phi", "euler cov", "midpoint cov"};
  for (int i = 0; i < 4; ++i) {
    std::cout << "[ measured ] " << what[i] << " vs rk4 over 2 s: " << at_200[i] << " at 200 Hz, "
              << at_100[i] << " at 100 Hz\n";
    EXPECT_LT(at_200[i], 1e-2) << what[i];
    // First order: halving the rate doubles the difference (the rk4 reference moves by O(dt^4)).
    EXPECT_GT(at_100[i] / at_200[i], 1.6) << what[i];
    EXPECT_LT(at_100[i] / at_200[i], 2.4) << what[i];
  }
}

}  // namespace
