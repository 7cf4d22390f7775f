// Hostile residual plugins and ids for NativeResidualFactor: every broken declaration or
// output is an imuconv::Error at construction naming the factor's id and what is wrong, never a
// crash; a cost at a non-finite state tells Ceres it failed.
#include <gtest/gtest.h>

#include <limits>

#include "imuconv_test.h"
#include "jacobian_check.h"
#include "native_problem.h"
#include "text_contains.h"

namespace imuconv::ceres_test {
namespace {

// A third-party factor: r = p_e - p_s (3 rows), declared in the left chart, with switches that
// break it one way at a time.
class ToyResidual final : public ResidualFactor {
 public:
  ResidualCostSpec spec{"r",
                        "left",
                        ResidualWeighting::SqrtInformation,
                        "W",
                        {{"J0", 0, ::imuconv::Block::p}},
                        {{"J1", 0, ::imuconv::Block::p}}};
  bool declares = true, writes_weighting = true, writes_nan = false, wide_weighting = false;
  Mat3 weighting = 2.0 * Mat3::Identity();

  const char* id() const noexcept override { return "toy"; }
  const char* increment_convention() const noexcept override { return "forster"; }
  const char* layout() const noexcept override { return "toy: r = p_e - p_s"; }
  int degrees_of_freedom() const noexcept override { return 3; }
  Status evaluate(const Preintegrated&, const ImuState& x_s, const ImuState& x_e, const Vec3&,
                  ResidualSink& sink) const noexcept override {
    Vec3 r = x_e.p - x_s.p;
    if (writes_nan) r.y() = std::numeric_limits<double>::quiet_NaN();
    WriteVector(sink, "r", r);
    WriteMatrix(sink, "J0", Mat3(-Mat3::Identity()));
    WriteMatrix(sink, "J1", Mat3(Mat3::Identity()));
    if (wide_weighting)
      WriteMatrix(sink, "W", Eigen::Matrix<double, 3, 4>::Ones());
    else if (writes_weighting)
      WriteMatrix(sink, "W", weighting);
    return Status::Ok();
  }
  const ResidualCostSpec* cost_spec() const noexcept override { return declares ? &spec : nullptr; }
};

// The message of the Error that building the factor throws ("" if none).
std::string ToyError(const RunWithMethod& d, const ToyResidual& toy) {
  try {
    NativeResidualFactor f(test::Plugins(), std::make_shared<ToyResidual>(toy), d.method,
                           d.run.samples, 0.0, 0.2, SimulatedNoise(), Vec3::Zero(), Vec3::Zero());
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

::testing::AssertionResult SaysBoth(const std::string& message, const std::string& a,
                                    const std::string& b) {
  if (test::Has(message, a) && test::Has(message, b)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "expected an error saying '" << a << "' and '" << b << "', got '" << message << "'";
}

TEST(NativeResidualHostileInput, UnknownIdIsAnErrorListingTheKnownOnes) {
  const RunWithMethod d = NoiseFreeZeroBiasRun(test::Plugins());
  std::string message;
  try {
    NativeResidualFactor f(test::Plugins(), "vins_fusoin", d.method, d.run.samples, 0.0, 0.2,
                           SimulatedNoise(), Vec3::Zero(), Vec3::Zero());
  } catch (const Error& e) {
    message = e.what();
  }
  const std::string known = test::Plugins().ids(PluginKind::Residual).front();
  EXPECT_TRUE(SaysBoth(message, "native residual factor 'vins_fusoin'", known));
}

TEST(NativeResidualHostileInput, BrokenDeclarationsAndOutputsAreErrorsNamingTheFactor) {
  const RunWithMethod d = NoiseFreeZeroBiasRun(test::Plugins());
  const std::string who = "native residual factor 'toy'";
  ToyResidual toy;
  EXPECT_EQ(ToyError(d, toy), "");  // the healthy toy builds

  ToyResidual t = toy;
  t.declares = false;
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "declares no cost"));
  t = toy;
  t.writes_weighting = false;
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "wrote no 'W'"));
  t = toy;
  t.writes_nan = true;
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "'r' is not finite"));
  t = toy;
  t.spec.residual = "nothing";
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "wrote no 'nothing'"));
  t = toy;
  t.spec.residual = nullptr;
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "residual is not a name"));
  t = toy;
  t.spec.state_convention = "no_such_chart";
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "'no_such_chart', which is not registered"));
  t = toy;
  t.spec.start[1] = {"J0", 0, ::imuconv::Block::p};
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "block 'p' twice"));
  t = toy;
  t.spec.start[0].first_column = 1;  // J0 is 3x3: columns 1..3 do not exist
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "at least 4 columns"));
  t = toy;
  t.spec.start[0].block = static_cast<::imuconv::Block>(9);
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "names no tangent block"));
  t = toy;
  t.spec.weighting = static_cast<ResidualWeighting>(7);
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "weighting 7"));
  t = toy;
  t.spec.weighting = ResidualWeighting::Information;
  t.weighting = -Mat3::Identity();
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "not positive semi-definite"));
  t = toy;
  t.spec.weighting = ResidualWeighting::Information;
  t.wide_weighting = true;  // 3x4: no information of a 3-vector
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "its weighting 'W' is 3x4 (expected 3x3)"));
  t = toy;
  t.spec.weighting = ResidualWeighting::MeasurementCovariance;  // and still names "W"
  EXPECT_TRUE(SaysBoth(ToyError(d, t), who, "expected null"));
}

TEST(NativeResidualHostileInput, AThirdPartyFactorIsACostWithExactJacobians) {
  // Nothing of the toy is known to imuconv::ceres but its declaration: its cost is W (p_e - p_s)
  // with Jacobians through the left chart, checked as cost_jacobians.cpp checks the others.
  const RunWithMethod d = NoiseFreeZeroBiasRun(test::Plugins());
  const NativeResidualFactor f(test::Plugins(), std::make_shared<ToyResidual>(), d.method,
                               d.run.samples, 0.0, 0.2, SimulatedNoise(), Vec3::Zero(),
                               Vec3::Zero());
  std::unique_ptr<::ceres::CostFunction> cost(f.MakeCostFunction());
  std::array<double, kStateBlockSize> bs, be;
  ToStateBlock(Perturbed(d.run.truth[0], 0), bs.data());
  ToStateBlock(Perturbed(d.run.truth[1], 1), be.data());
  for (const std::string& conv : test::Plugins().ids(PluginKind::StateConvention)) {
    const StateManifold M(test::Plugins(), conv);
    // h = 1e-6 on a residual linear in p and of size ~1: round-off 1e-16 / 1e-6 = 1e-10.
    EXPECT_LT(TangentJacobianError(*cost, {bs.data(), be.data()}, {&M, &M}), 1e-8) << conv;
  }
}

TEST(NativeResidualHostileInput, PluginErrorsAndNonFiniteStates) {
  const RunWithMethod d = NoiseFreeZeroBiasRun(test::Plugins());
  const Registry& reg = test::Plugins();
  // The plugin's own Status: ORB-SLAM3's EdgeInertial has gravity (0, 0, -9.81) only.
  PreintegrationFactorOptions fo;
  fo.gravity = Vec3(0.0, 0.0, -9.7);
  if (reg.has(PluginKind::Residual, "orb_slam3")) {
    std::string message;
    try {
      NativeResidualFactor f(reg, "orb_slam3", d.method, d.run.samples, 0.0, 0.2, SimulatedNoise(),
                             Vec3::Zero(), Vec3::Zero(), fo);
    } catch (const Error& e) {
      message = e.what();
    }
    EXPECT_TRUE(SaysBoth(message, "native residual factor 'orb_slam3'", "gravity"));
  }
  // A noise-free measurement: the measurement has no covariance to whiten with.
  for (const std::string& id : reg.ids(PluginKind::Residual)) {
    std::string message;
    try {
      NativeResidualFactor f(reg, id, d.method, d.run.samples, 0.0, 0.2, ImuNoise{}, Vec3::Zero(),
                             Vec3::Zero());
    } catch (const Error& e) {
      message = e.what();
    }
    EXPECT_TRUE(SaysBoth(message, "native residual factor '" + id + "'", "positive definite"));
  }
  // A non-finite state: the cost fails (Ceres shortens its step), Evaluate names the factor.
  for (const std::string& id : reg.ids(PluginKind::Residual)) {
    const NativeResidualFactor f(reg, id, d.method, d.run.samples, 0.0, 0.2, SimulatedNoise(),
                                 Vec3::Zero(), Vec3::Zero());
    std::unique_ptr<::ceres::CostFunction> cost(f.MakeCostFunction());
    std::array<double, kStateBlockSize> bs, be;
    ToStateBlock(d.run.truth[0], bs.data());
    ToStateBlock(d.run.truth[1], be.data());
    be[block_idx::v] = std::numeric_limits<double>::quiet_NaN();
    const double* blocks[] = {bs.data(), be.data()};
    Eigen::VectorXd r(cost->num_residuals());
    EXPECT_FALSE(cost->Evaluate(blocks, r.data(), nullptr)) << id;
    ImuState bad = d.run.truth[1];
    bad.v.x() = std::numeric_limits<double>::quiet_NaN();
    std::string message;
    try {
      (void)f.Evaluate(d.run.truth[0], bad);
    } catch (const Error& e) {
      message = e.what();
    }
    EXPECT_TRUE(test::Has(message, "native residual factor '" + id + "'")) << message;
  }
}

}  // namespace
}  // namespace imuconv::ceres_test
