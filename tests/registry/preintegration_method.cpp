// A preintegrate task's method resolved once (ResolvePreintegrationMethod) gives, bit for bit,
// what the id-based paths give: the propagator run through Registry::propagate in `left`, and
// a native scheme's output brought into preint_reference by FromConvention.
#include <gtest/gtest.h>

#include <map>

#include "../bridge/synthetic.h"
#include "imuconv/bridge.h"
#include "imuconv/preintegrator.h"
#include "imuconv_test.h"

namespace {

using namespace imuconv;
using imuconv::test::Plugins;

// A window over samples that live as long as the test binary (a window points into them).
SampleWindow Window(double seconds) {
  static std::map<double, std::vector<ImuSample>> kept;
  const auto& s = kept.emplace(seconds, test::SmoothImu(seconds)).first->second;
  SampleWindow w;
  const bool made = MakeWindow(s.data(), s.size(), s.front().t, s.back().t, w).ok();
  EXPECT_TRUE(made) << seconds << " s window";
  return w;
}

const Vec3 kBg(0.01, -0.02, 0.005), kBa(0.1, 0.05, -0.2);

std::string ErrorOf(PluginKind kind, const char* id) {
  try {
    (void)ResolvePreintegrationMethod(Plugins(), kind, id);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Exact equality on purpose: the resolved path must do the same floating-point operations.
void ExpectSame(const Preintegrated& a, const Preintegrated& b) {
  EXPECT_EQ(a.dt, b.dt);
  EXPECT_TRUE(a.delta.dR == b.delta.dR && a.delta.dp == b.delta.dp && a.delta.dv == b.delta.dv);
  EXPECT_TRUE(a.delta.dbg == b.delta.dbg && a.delta.dba == b.delta.dba);
  EXPECT_TRUE(a.J_bias == b.J_bias) << (a.J_bias - b.J_bias).cwiseAbs().maxCoeff();
  EXPECT_TRUE(a.cov == b.cov) << (a.cov - b.cov).cwiseAbs().maxCoeff();
}

TEST(PreintegrationMethod, PropagatorResolvedWithItsNativeConvention) {
  for (const char* id : {"euler", "midpoint", "rk4"}) {
    const PreintegrationMethod m =
        ResolvePreintegrationMethod(Plugins(), PluginKind::Propagator, id);
    ASSERT_TRUE(m.propagator && !m.preintegrator) << id;
    EXPECT_STREQ(m.native_state->id(), m.propagator->native_convention()) << id;
    EXPECT_STREQ(m.reference_state->id(), "left") << id;

    // The end state of Registry::propagate from the identity is the increment itself.
    const SampleWindow w = Window(0.5);
    PropagationInput in;
    in.x_s.bg = kBg;
    in.x_s.ba = kBa;
    in.noise = test::TestNoise();
    in.gravity.setZero();
    in.window = w;
    const PropagationResult r = Plugins().propagate(id, "left", in);
    const Preintegrated p = Preintegrate(Plugins(), m, w, kBg, kBa, test::TestNoise());
    EXPECT_TRUE(p.delta.dR == r.x_e.R && p.delta.dp == r.x_e.p && p.delta.dv == r.x_e.v) << id;
    ExpectSame(p, PreintegrateByPropagation(Plugins(), id, w, kBg, kBa, test::TestNoise()));
  }
}

TEST(PreintegrationMethod, PreintegratorMatchesFromConvention) {
  for (const char* id : {"tangent", "manifold"}) {
    const PreintegrationMethod m =
        ResolvePreintegrationMethod(Plugins(), PluginKind::Preintegrator, id);
    ASSERT_TRUE(m.preintegrator && !m.propagator) << id;
    EXPECT_STREQ(m.cov_convention->id(), m.preintegrator->cov_convention()) << id;
    EXPECT_STREQ(m.jacobian_convention->id(), m.preintegrator->jacobian_convention()) << id;

    const SampleWindow w = Window(0.5);
    const PreintegrationInput in = PreintegrationInputOf(w, kBg, kBa, test::TestNoise());
    Preintegrated native;
    ASSERT_TRUE(m.preintegrator->integrate(in, native).ok());
    native.convention = m.preintegrator->cov_convention();
    native.jacobian_convention = m.preintegrator->jacobian_convention();
    ExpectSame(Preintegrate(Plugins(), m, w, kBg, kBa, test::TestNoise()),
               FromConvention(Plugins(), native));
  }
}

TEST(PreintegrationMethod, UnknownIdListsTheKnownOnes) {
  const std::string msg = ErrorOf(PluginKind::Propagator, "rk5");
  EXPECT_NE(msg.find("'rk5'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("rk4"), std::string::npos) << msg;
  // A preintegrator's id is not a propagator's.
  const std::string other = ErrorOf(PluginKind::Propagator, "tangent");
  EXPECT_NE(other.find("'tangent'"), std::string::npos) << other;
  EXPECT_NE(ErrorOf(PluginKind::Preintegrator, "rk4").find("known: "), std::string::npos);
}

TEST(PreintegrationMethod, ConventionIsNotAMethod) {
  const std::string msg = ErrorOf(PluginKind::StateConvention, "left");
  EXPECT_NE(msg.find("is a propagator or a preintegrator"), std::string::npos) << msg;
}

TEST(PreintegrationMethod, UnresolvedMethodIsAnError) {
  PreintegrationMethod m;
  m.id = "rk4";
  const SampleWindow w = Window(0.1);
  EXPECT_THROW(Preintegrate(Plugins(), m, w, kBg, kBa, test::TestNoise()), Error);
}

}  // namespace
