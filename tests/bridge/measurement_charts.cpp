// The one measurement type (imuconv/preintegrated.h): its two convention labels say the charts
// of its numbers, every bridge function takes it in any charts, and a native preintegrator
// still writes only the numbers, at the places it wrote them before the labels were added (the
// plugin ABI was not changed by them: kPluginAbiVersion stayed 2).
#include <gtest/gtest.h>

#include <cstddef>

#include "imuconv/bridge.h"
#include "imuconv/preintegrator.h"
#include "imuconv/reference_charts.h"
#include "imuconv_test.h"
#include "scale_aware.h"
#include "synthetic.h"

namespace {

using namespace imuconv;
using imuconv::test::Plugins;

constexpr const char* kRef = ReferenceChart<PreintIncrement>::id;

// Charts with other block orders, signs and bias-Jacobian charts than the reference one:
// GTSAM's (J_bias in a chart of its own), VINS-Fusion's and Basalt's (p before theta), Forster's
// (negated perturbation).
const char* const kCharts[] = {"gtsam_manifold", "gtsam_tangent", "vins_fusion", "basalt",
                               "forster"};

// A round trip through a chart and back multiplies by a conversion and its inverse, each a
// product of 15x15 matrices whose entries are O(1) to O(10) at this 1 s increment: the round-off
// is a few 1e-15 of the scale; 1e-10 leaves four orders of magnitude for it, while a chart taken
// for another (a block order, a sign, a bias Jacobian's rows) is wrong by O(1) on that scale.
constexpr double kRoundTrip = 1e-10;

struct ChartScenario {
  std::vector<ImuSample> imu = test::SmoothImu(1.0);
  SampleWindow w;
  Vec3 bg = Vec3(0.01, -0.02, 0.005), ba = Vec3(0.1, 0.05, -0.2);
  ImuState x_s, x_e;
  Mat15 cov_s = Mat15::Identity() * 1e-4;
  Vec3 g = Vec3(0, 0, -9.81);
  Preintegrated m;
  ChartScenario() {
    EXPECT_TRUE(MakeWindow(imu.data(), imu.size(), imu.front().t, imu.back().t, w).ok());
    m = PreintegrateNative(Plugins(), "manifold", w, bg, ba, test::TestNoise());
    x_s.R = so3::Exp(Vec3(0.3, -1.1, 0.7));
    x_s.p = Vec3(3, -2, 1);
    x_s.v = Vec3(0.5, 1.5, -0.2);
    x_s.bg = bg + Vec3(1e-3, -2e-3,
                       1e-3);  // not the measurement's estimate: the correction is exercised
    x_s.ba = ba + Vec3(-0.01, 0.02, 0.01);
    Vec15 d;
    d << 0.02, -0.01, 0.03, 0.05, -0.02, 0.01, 0.03, 0.02, -0.04, 1e-3, -2e-3, 5e-4, 0.01, -0.02,
        0.03;
    LeftRetract(Predict(x_s, m.delta, m.dt, g), d, x_e);
  }
  /// What `m` is the preintegration of: the window at the bias estimate, with the test noise.
  PreintegrationInput Input() const { return PreintegrationInputOf(w, bg, ba, test::TestNoise()); }
};

double MaxRelative(const Eigen::MatrixXd& ref, const Eigen::MatrixXd& est) {
  return (ref - est).cwiseAbs().maxCoeff() / std::max(ref.cwiseAbs().maxCoeff(), 1e-300);
}

TEST(MeasurementCharts, PreintegrationIsLabelledWithTheReferenceCharts) {
  const ChartScenario s;
  EXPECT_EQ(s.m.convention, kRef);
  EXPECT_EQ(s.m.jacobian_convention, kRef);
  EXPECT_TRUE(s.m.in_reference_charts());
  const Preintegrated p =
      PreintegrateByPropagation(Plugins(), "rk4", s.w, s.bg, s.ba, test::TestNoise());
  EXPECT_TRUE(p.in_reference_charts());
}

TEST(MeasurementCharts, ExpressNamesItsChartsAndFromConventionReadsThem) {
  const ChartScenario s;
  for (const char* c : kCharts) {
    SCOPED_TRACE(c);
    const Preintegrated e = Express(Plugins(), s.m, c);
    EXPECT_EQ(e.convention, c);
    EXPECT_EQ(e.jacobian_convention,
              Plugins().info(PluginKind::IncrementConvention, c).jacobian_convention);
    EXPECT_FALSE(e.in_reference_charts());
    const Preintegrated back = FromConvention(Plugins(), e);
    EXPECT_TRUE(back.in_reference_charts());
    EXPECT_LE(test::CorrelationScaleDiff(s.m.cov, back.cov).d, kRoundTrip);
    EXPECT_LE(MaxRelative(s.m.J_bias, back.J_bias), kRoundTrip);
  }
}

// What failed in silence before: a measurement in a convention's charts handed to the
// computations written in preint_reference. Now each brings it into those charts first and
// gives the answer of the reference measurement.
TEST(MeasurementCharts, ComputationsTakeAMeasurementInAnyCharts) {
  const ChartScenario s;
  const PropagationResult p_ref =
      PropagateByPreintegration(Plugins(), s.m, s.x_s, s.cov_s, "forster", s.g);
  const Residual r_ref =
      ComputeResidual(Plugins(), ResidualKind::Gtsam, s.m, s.x_s, s.x_e, "gtsam_navstate", s.g);
  const PreintIncrement c_ref =
      BiasCorrectedDelta(Plugins(), s.m, "gtsam_manifold_jacobian", s.x_s.bg, s.x_s.ba);
  for (const char* c : kCharts) {
    SCOPED_TRACE(c);
    const Preintegrated e = Express(Plugins(), s.m, c);
    const PropagationResult p =
        PropagateByPreintegration(Plugins(), e, s.x_s, s.cov_s, "forster", s.g);
    EXPECT_LE(test::CorrelationScaleDiff(p_ref.cov, p.cov).d, kRoundTrip);
    EXPECT_LE(MaxRelative(p_ref.Phi, p.Phi), kRoundTrip);
    EXPECT_LE((p_ref.x_e.p - p.x_e.p).norm(), kRoundTrip * p_ref.x_e.p.norm());
    const Residual r =
        ComputeResidual(Plugins(), ResidualKind::Gtsam, e, s.x_s, s.x_e, "gtsam_navstate", s.g);
    EXPECT_LE(MaxRelative(r_ref.r, r.r), kRoundTrip);
    EXPECT_LE(test::CorrelationScaleDiff(r_ref.cov, r.cov).d, kRoundTrip);
    EXPECT_LE(MaxRelative(r_ref.H_start, r.H_start), kRoundTrip);
    const PreintIncrement d =
        BiasCorrectedDelta(Plugins(), e, "gtsam_manifold_jacobian", s.x_s.bg, s.x_s.ba);
    EXPECT_LE(so3::Log(c_ref.dR.transpose() * d.dR).norm(), kRoundTrip);
    EXPECT_LE((c_ref.dp - d.dp).norm(), kRoundTrip * c_ref.dp.norm());
    // Expressing an expressed measurement in another chart goes through the reference one.
    const Preintegrated again = Express(Plugins(), e, "basalt");
    const Preintegrated direct = Express(Plugins(), s.m, "basalt");
    EXPECT_EQ(again.convention, "basalt");
    EXPECT_LE(test::CorrelationScaleDiff(direct.cov, again.cov).d, kRoundTrip);
  }
}

TEST(MeasurementCharts, AnUnknownChartIsAnErrorNamingIt) {
  const ChartScenario s;
  Preintegrated e = Express(Plugins(), s.m, "vins_fusion");
  e.convention = "no_such_chart";
  try {
    (void)PropagateByPreintegration(Plugins(), e, s.x_s, s.cov_s, "left", s.g);
    ADD_FAILURE() << "an unknown chart was taken";
  } catch (const Error& err) {
    EXPECT_NE(std::string(err.what()).find("no_such_chart"), std::string::npos) << err.what();
  }
}

// A kernel's or a plugin's raw output states no charts: computing with it as if it were in
// the reference charts would be a wrong answer given in silence.
TEST(MeasurementCharts, AMeasurementWhoseChartsAreNotStatedIsRefused) {
  const ChartScenario s;
  const PreintegrationInput in = s.Input();
  Preintegrated raw;
  ASSERT_TRUE(Plugins().preintegrator("manifold")->integrate(in, raw).ok());
  EXPECT_TRUE(raw.convention.empty());
  for (int call = 0; call < 3; ++call) {
    SCOPED_TRACE(call);
    try {
      if (call == 0) (void)Express(Plugins(), raw, "forster");
      if (call == 1) (void)PropagateByPreintegration(Plugins(), raw, s.x_s, s.cov_s, "left", s.g);
      if (call == 2) (void)FromConvention(Plugins(), raw);
      ADD_FAILURE() << "a measurement without charts was taken";
    } catch (const Error& err) {
      EXPECT_NE(std::string(err.what()).find("charts are not stated"), std::string::npos)
          << err.what();
    }
  }
  // Stated, the same numbers are GTSAM's manifold measurement, as the preintegrate path takes them.
  raw.convention = "gtsam_manifold";
  raw.jacobian_convention = "gtsam_manifold_jacobian";
  const Preintegrated imported = FromConvention(Plugins(), raw);
  EXPECT_EQ((imported.cov - s.m.cov).cwiseAbs().maxCoeff(),
            0.0);  // the same operations as Preintegrate
  EXPECT_EQ((imported.J_bias - s.m.J_bias).cwiseAbs().maxCoeff(), 0.0);
}

// The plugin writes the numbers and never the labels: the host sets those, so no std::string
// is made or freed on the plugin's side (preintegrated.h).
TEST(MeasurementCharts, ANativePreintegratorLeavesTheLabelsAlone) {
  const ChartScenario s;
  for (const char* id : {"manifold", "tangent", "vins_fusion", "basalt"}) {
    SCOPED_TRACE(id);
    const PreintegrationInput in = s.Input();
    Preintegrated out;
    out.convention = "label set before the call";
    out.jacobian_convention = "another label set before the call";
    ASSERT_TRUE(Plugins().preintegrator(id)->integrate(in, out).ok());
    EXPECT_EQ(out.convention, "label set before the call");
    EXPECT_EQ(out.jacobian_convention, "another label set before the call");
    EXPECT_GT(out.dt, 0.0);
    EXPECT_GT(out.cov.diagonal().minCoeff(), 0.0);
  }
}

// The output type of ABI version 2 as it was declared, member for member: a plugin built against
// it writes these offsets, so the numbers of Preintegrated must stay at them.
struct AbiVersion2Output {
  double dt = 0.0;
  PreintIncrement delta;
  Vec3 bg_hat = Vec3::Zero(), ba_hat = Vec3::Zero();
  Mat15 cov = Mat15::Zero();
  Mat96 J_bias = Mat96::Zero();
};

template <class Struct, class Member>
std::ptrdiff_t OffsetOf(const Struct& s, const Member& m) {
  return reinterpret_cast<const char*>(&m) - reinterpret_cast<const char*>(&s);
}

TEST(MeasurementAbi, TheNumbersKeepTheLayoutOfAbiVersion2) {
  const Preintegrated now;
  const AbiVersion2Output then;
  EXPECT_EQ(OffsetOf(now, now.dt), OffsetOf(then, then.dt));
  EXPECT_EQ(OffsetOf(now, now.delta), OffsetOf(then, then.delta));
  EXPECT_EQ(OffsetOf(now, now.bg_hat), OffsetOf(then, then.bg_hat));
  EXPECT_EQ(OffsetOf(now, now.ba_hat), OffsetOf(then, then.ba_hat));
  EXPECT_EQ(OffsetOf(now, now.cov), OffsetOf(then, then.cov));
  EXPECT_EQ(OffsetOf(now, now.J_bias), OffsetOf(then, then.J_bias));
  // The labels come after every number.
  EXPECT_GE(OffsetOf(now, now.convention), static_cast<std::ptrdiff_t>(sizeof(AbiVersion2Output)));
  EXPECT_EQ(alignof(Preintegrated), alignof(AbiVersion2Output));
}

}  // namespace
