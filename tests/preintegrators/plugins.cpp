// The `tangent` and `manifold` plugins through the registry: ids and conventions, the
// conventions they name are registered with GTSAM's block order, the output's fixed parts,
// re-integration with a new bias, and bad input returning a Status (never throwing; the
// interface is noexcept, so a throw would terminate the test binary).
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

#include "imuconv_test.h"
#include "reference_cases.h"
#include "scheme_fact_declarations.h"

namespace {

// What GTSAM's two schemes say of their noise and mean (scheme_fact_declarations.h;
// docs/montecarlo.md): both hold each sample over the step it starts and read continuous
// densities; both give the mean alone (kernels/mean_only.h: the recursion with its covariance
// off).
IMUCONV_SCHEME_FACTS(Preintegrator, manifold, kForward, kContinuous, true, kProvided);
IMUCONV_SCHEME_FACTS(Preintegrator, tangent, kForward, kContinuous, true, kProvided);

using namespace imuconv;
using namespace imuconv::test;

struct Expected {
  const char* id;
  const char* cov;
  const char* jac;
};
const Expected kSchemes[] = {{"tangent", "gtsam_tangent", "gtsam_tangent"},
                             {"manifold", "gtsam_manifold", "gtsam_manifold_jacobian"}};

TEST(PreintegratorPlugins, LoadThroughTheRegistry) {
  for (const Expected& e : kSchemes) {
    SCOPED_TRACE(e.id);
    ASSERT_TRUE(Plugins().has(PluginKind::Preintegrator, e.id));
    const auto pre = Plugins().preintegrator(e.id);
    EXPECT_STREQ(pre->id(), e.id);
    EXPECT_STREQ(pre->cov_convention(), e.cov);
    EXPECT_STREQ(pre->jacobian_convention(), e.jac);
    const PluginInfo& info = Plugins().info(PluginKind::Preintegrator, e.id);
    EXPECT_EQ(info.native_convention, e.cov);
    EXPECT_EQ(info.jacobian_convention, e.jac);
    EXPECT_NE(info.file.find("imuconv_plugin_preintegrators_" + std::string(e.id) + ".so"),
              std::string::npos);
  }
}

TEST(PreintegratorPlugins, NamedConventionsUseGtsamBlockOrder) {
  // The covariance is laid out [theta, p, v, ba, bg] (GTSAM's preintMeasCov); the
  // conventions it is declared in must say so, or conversions would permute blocks.
  const std::vector<std::string> gtsam_order = {"theta", "p", "v", "ba", "bg"};
  for (const char* conv : {"gtsam_tangent", "gtsam_manifold", "gtsam_manifold_jacobian"}) {
    SCOPED_TRACE(conv);
    ASSERT_TRUE(Plugins().has(PluginKind::IncrementConvention, conv));
    EXPECT_EQ(Plugins().info(PluginKind::IncrementConvention, conv).blocks, gtsam_order);
  }
  EXPECT_EQ(Plugins().info(PluginKind::IncrementConvention, "gtsam_manifold").jacobian_convention,
            "gtsam_manifold_jacobian");
}

TEST(PreintegratorPlugins, OutputFixedParts) {
  const ReferenceCase rc = LoadReferenceCase("smooth-1");
  const PreintegrationInput in = rc.Input();
  for (const Expected& e : kSchemes) {
    SCOPED_TRACE(e.id);
    Preintegrated out;
    ASSERT_TRUE(Plugins().preintegrator(e.id)->integrate(in, out).ok());
    EXPECT_EQ(out.bg_hat, rc.bg);
    EXPECT_EQ(out.ba_hat, rc.ba);
    EXPECT_EQ(out.delta.dbg, Vec3::Zero());  // the estimate of the random walk is zero
    EXPECT_EQ(out.delta.dba, Vec3::Zero());
    EXPECT_EQ(out.cov, out.cov.transpose());  // symmetric by construction, exactly
    // Bias block: exactly the accumulated random walk, uncorrelated between ba and bg.
    const double T = out.dt;
    const double qa = rc.noise.accel_random_walk, qg = rc.noise.gyro_random_walk;
    // Sum of 2000 terms dt q^2 against T q^2: rounding only (2000 ulps ~ 4e-13 at worst).
    EXPECT_NEAR(out.cov(9, 9), T * qa * qa, 1e-12 * T * qa * qa);
    EXPECT_NEAR(out.cov(12, 12), T * qg * qg, 1e-12 * T * qg * qg);
    EXPECT_EQ(out.cov(9, 12), 0.0);
    // theta does not depend on the accelerometer bias in either scheme.
    EXPECT_TRUE((out.J_bias.block<3, 3>(0, 0).array() == 0.0).all());
    // Orthonormal rotation: 2000 products of rotations drift by ~sqrt(2000) ulps (manifold),
    // one Exp is exact to a few ulps (tangent); 1e-13 is ~500 ulps.
    EXPECT_LT((out.delta.dR.transpose() * out.delta.dR - Mat3::Identity()).cwiseAbs().maxCoeff(),
              1e-13);
  }
}

TEST(PreintegratorPlugins, ReintegrationWithANewBiasIsJustAnotherCall) {
  // First-order bias correction with J_bias against re-integration with the reference's
  // bias_delta: they differ by the second-order term only, so the gap must shrink 4x when
  // the bias change is halved (a consistency check of J_bias's chart and column order).
  const ReferenceCase rc = LoadReferenceCase("smooth-0");
  const nlohmann::json c = ReadJson(DataPath("reference/cases/smooth-0.json"));
  const Vec3 dbg = JsonVec3(c.at("bias_delta").at("bg")),
             dba = JsonVec3(c.at("bias_delta").at("ba"));
  const PreintegrationInput in = rc.Input();
  const auto pre = Plugins().preintegrator("manifold");
  Preintegrated out0;
  ASSERT_TRUE(pre->integrate(in, out0).ok());
  double gap[2];
  for (int half = 0; half < 2; ++half) {
    const double s = half ? 0.5 : 1.0;
    Eigen::Matrix<double, 6, 1> db;
    db << s * dba, s * dbg;  // columns [ba, bg]
    PreintegrationInput in1 = in;
    in1.ba += s * dba;
    in1.bg += s * dbg;
    Preintegrated out1;
    ASSERT_TRUE(pre->integrate(in1, out1).ok());
    EXPECT_EQ(out1.ba_hat, in1.ba);
    const Vec9 predicted = out0.J_bias * db;
    Vec9 actual;
    actual << so3::Log(out0.delta.dR.transpose() * out1.delta.dR), out1.delta.dp - out0.delta.dp,
        out1.delta.dv - out0.delta.dv;
    gap[half] = (actual - predicted).norm();
  }
  std::printf("[ bias    ] |re-integration - first order|: %.3e (db), %.3e (db/2), ratio %.3f\n",
              gap[0], gap[1], gap[0] / gap[1]);
  EXPECT_GT(gap[0], 0.0);
  // The gap is O(db^2): ratio 4, moved only by third-order terms (relative size ~|db||J|,
  // a few percent at most here); a wrong chart or column order would leave an O(db) gap.
  EXPECT_NEAR(gap[0] / gap[1], 4.0, 0.2) << gap[0] << " " << gap[1];
}

// ---- bad input ------------------------------------------------------------------------

void ExpectError(const PreintegrationInput& in, const std::string& what) {
  for (const Expected& e : kSchemes) {
    Preintegrated out;
    Status st;
    EXPECT_NO_THROW(st = Plugins().preintegrator(e.id)->integrate(in, out)) << e.id << ": " << what;
    EXPECT_FALSE(st.ok()) << e.id << ": " << what;
    EXPECT_FALSE(st.message().empty()) << e.id << ": " << what;
  }
}

std::vector<ImuSample> ThreeSamples() {
  std::vector<ImuSample> s(3);
  for (int i = 0; i < 3; ++i) {
    s[i].t = 1.0 + 0.005 * i;
    s[i].gyro = Vec3(0.1, -0.2, 0.3);
    s[i].accel = Vec3(0.0, 0.0, 9.81);
  }
  return s;
}

TEST(PreintegratorPlugins, BadWindowsReturnAnError) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<ImuSample> good = ThreeSamples();
  PreintegrationInput base;
  base.noise.gyro_noise_density = 1e-3;
  base.noise.accel_noise_density = 1e-2;
  base.window = WindowOver(good);
  {
    Preintegrated out;
    ASSERT_TRUE(Plugins().preintegrator("tangent")->integrate(base, out).ok());
  }

  PreintegrationInput in = base;
  in.window.begin = 1;
  in.window.end = 0;  // size() == 1
  ExpectError(in, "one knot");
  in.window.begin = 2;  // size() == 0
  ExpectError(in, "no knots");
  in = base;
  in.window.samples = nullptr;  // interior knots but no sample array
  ExpectError(in, "null samples");
  in = base;
  in.window = SampleWindow{};  // default: first == last, t not increasing
  ExpectError(in, "default window");

  const auto with = [&](auto mutate, const std::string& what) {
    std::vector<ImuSample> s = good;
    mutate(s);
    PreintegrationInput i = base;
    i.window = WindowOver(s);
    ExpectError(i, what);
  };
  with([&](std::vector<ImuSample>& s) { s[1].gyro.y() = nan; }, "NaN gyro");
  with([&](std::vector<ImuSample>& s) { s[0].accel.z() = inf; }, "inf accel");
  with([&](std::vector<ImuSample>& s) { s[2].t = nan; }, "NaN time");
  with([&](std::vector<ImuSample>& s) { s[2].t = s[1].t; }, "repeated time");
  with([&](std::vector<ImuSample>& s) { std::swap(s[0].t, s[1].t); }, "decreasing time");

  in = base;
  in.bg.x() = nan;
  ExpectError(in, "NaN gyro bias");
  in = base;
  in.noise.accel_random_walk = -1.0;
  ExpectError(in, "negative noise density");
  in = base;
  in.noise.gyro_noise_density = inf;
  ExpectError(in, "infinite noise density");
}

}  // namespace
