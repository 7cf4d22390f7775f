// Hostile input to the factors: every bad argument is an imuconv::Error that says what is wrong,
// never a crash or a silent wrong cost; a cost at a non-finite state tells Ceres it failed.
#include <gtest/gtest.h>

#include <limits>

#include "ceres_problem.h"
#include "imuconv_test.h"
#include "text_contains.h"

namespace imuconv::ceres_test {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Whether an error message holds `piece`; on failure, the message (or that there was none).
::testing::AssertionResult Says(const std::string& message, const std::string& piece) {
  if (test::Has(message, piece)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "expected an error saying '" << piece << "', got '" << message << "'";
}

// The message of the Error that f throws ("" if it throws none).
template <class F>
std::string ErrorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string FactorError(const RunWithMethod& d, std::vector<ImuSample> samples, double t_s,
                        double t_e, const ImuNoise& noise = SimulatedNoise(),
                        const PreintegrationFactorOptions& fo = {},
                        const PreintegrationMethod* method = nullptr) {
  return ErrorOf([&] {
    PreintegrationFactor f(test::Plugins(), method ? *method : d.method, std::move(samples), t_s,
                           t_e, noise, Vec3::Zero(), Vec3::Zero(), fo);
  });
}

TEST(CeresHostileInput, PreintegrationFactorRefusesBadSamplesIntervalsAndNoise) {
  const RunWithMethod d = NoiseFreeZeroBiasRun(test::Plugins());
  EXPECT_EQ(FactorError(d, d.run.samples, 0.0, 0.2), "");

  std::vector<ImuSample> s = d.run.samples;
  s[5].gyro.y() = kNaN;
  EXPECT_TRUE(Says(FactorError(d, s, 0.0, 0.2), "IMU sample 5 has a non-finite"));
  s = d.run.samples;
  std::swap(s[7], s[8]);
  EXPECT_TRUE(Says(FactorError(d, s, 0.0, 0.2), "IMU sample 8 is not later"));
  s = d.run.samples;
  s[9].t = s[8].t;
  EXPECT_TRUE(Says(FactorError(d, s, 0.0, 0.2), "IMU sample 9 is not later"));

  EXPECT_TRUE(Says(FactorError(d, d.run.samples, 0.2, 0.1), "t_s < t_e"));
  EXPECT_TRUE(Says(FactorError(d, d.run.samples, 0.1, 0.1), "t_s < t_e"));
  EXPECT_TRUE(Says(FactorError(d, d.run.samples, kNaN, 0.1), "not a finite"));
  // Not covered by the samples (they end at 0.2 s): MakeWindow's message, prefixed.
  EXPECT_TRUE(Says(FactorError(d, d.run.samples, 0.0, 5.0), "preintegration factor: "));
  EXPECT_NE(FactorError(d, {}, 0.0, 0.2), "");

  ImuNoise zero;  // all densities 0: the residual covariance is singular
  EXPECT_TRUE(Says(FactorError(d, d.run.samples, 0.0, 0.2, zero), "not positive definite"));
  ImuNoise negative = SimulatedNoise();
  negative.accel_noise_density = -1.0;
  EXPECT_TRUE(Says(FactorError(d, d.run.samples, 0.0, 0.2, negative), "noise density"));

  PreintegrationFactorOptions fo;
  fo.reintegrate_gyro_bias = -1.0;
  EXPECT_TRUE(Says(FactorError(d, d.run.samples, 0.0, 0.2, SimulatedNoise(), fo), "threshold"));
  fo = {};
  fo.gravity.z() = kNaN;
  EXPECT_TRUE(Says(FactorError(d, d.run.samples, 0.0, 0.2, SimulatedNoise(), fo), "gravity"));

  const PreintegrationMethod unresolved;
  EXPECT_TRUE(Says(FactorError(d, d.run.samples, 0.0, 0.2, SimulatedNoise(), {}, &unresolved),
                   "not resolved"));
}

TEST(CeresHostileInput, ReintegrateAtANonFiniteBiasKeepsTheMeasurement) {
  const RunWithMethod d = NoiseFreeZeroBiasRun(test::Plugins());
  PreintegrationFactor f(test::Plugins(), d.method, d.run.samples, 0.0, 0.2, SimulatedNoise(),
                         Vec3::Zero(), Vec3::Zero());
  const Preintegrated before = f.measurement();
  EXPECT_THROW(f.Reintegrate(Vec3(kNaN, 0, 0), Vec3::Zero()), Error);
  EXPECT_EQ(f.measurement().delta.dp, before.delta.dp);
  EXPECT_EQ(f.measurement().bg_hat, before.bg_hat);
}

TEST(CeresHostileInput, CostsAtANonFiniteStateReportFailureToCeres) {
  const RunWithMethod d = NoiseFreeZeroBiasRun(test::Plugins());
  const PreintegrationFactor f(test::Plugins(), d.method, d.run.samples, 0.0, 0.2, SimulatedNoise(),
                               Vec3::Zero(), Vec3::Zero());
  std::unique_ptr<::ceres::CostFunction> cost(f.MakeCostFunction());
  std::array<double, kStateBlockSize> a, b;
  ToStateBlock(d.run.truth[0], a.data());
  ToStateBlock(d.run.truth[1], b.data());
  b[block_idx::v] = kNaN;
  const double* blocks[] = {a.data(), b.data()};
  double r[15];
  EXPECT_FALSE(cost->Evaluate(blocks, r, nullptr));
  std::unique_ptr<::ceres::CostFunction> pose(
      MakePoseMeasurement(Mat3::Identity(), Vec3::Zero(), 0.1, 0.1));
  b = a;
  b[block_idx::p] = kNaN;
  const double* one[] = {b.data()};
  EXPECT_FALSE(pose->Evaluate(one, r, nullptr));
  std::unique_ptr<::ceres::CostFunction> prior(
      MakeStatePrior(test::Plugins(), "left", ImuState{}, Mat15::Identity()));
  EXPECT_FALSE(prior->Evaluate(one, r, nullptr));
}

TEST(CeresHostileInput, PriorAndPoseMeasurementRefuseBadArguments) {
  const Registry& reg = test::Plugins();
  EXPECT_TRUE(Says(
      ErrorOf([&] { delete MakeStatePrior(reg, "no_such_chart", ImuState{}, Mat15::Identity()); }),
      "no_such_chart"));
  Mat15 cov = Mat15::Identity();
  cov(3, 3) = -1.0;
  EXPECT_TRUE(
      Says(ErrorOf([&] { delete MakeStatePrior(reg, "left", ImuState{}, cov); }), "covariance"));
  cov = Mat15::Identity();
  cov(0, 1) = 0.5;  // not symmetric
  EXPECT_NE(ErrorOf([&] { delete MakeStatePrior(reg, "left", ImuState{}, cov); }), "");
  ImuState bad;
  bad.R(0, 0) = 2.0;
  EXPECT_TRUE(Says(ErrorOf([&] { delete MakeStatePrior(reg, "left", bad, Mat15::Identity()); }),
                   "rotation"));

  for (double sigma : {0.0, -1.0, kNaN, std::numeric_limits<double>::infinity()}) {
    EXPECT_TRUE(Says(
        ErrorOf([&] { delete MakePoseMeasurement(Mat3::Identity(), Vec3::Zero(), sigma, 0.1); }),
        "sigma"));
    EXPECT_TRUE(Says(
        ErrorOf([&] { delete MakePoseMeasurement(Mat3::Identity(), Vec3::Zero(), 0.1, sigma); }),
        "sigma"));
  }
  Mat3 reflection = Mat3::Identity();
  reflection(2, 2) = -1.0;
  EXPECT_TRUE(Says(ErrorOf([&] { delete MakePoseMeasurement(reflection, Vec3::Zero(), 0.1, 0.1); }),
                   "not a rotation"));
  EXPECT_TRUE(Says(
      ErrorOf([&] { delete MakePoseMeasurement(Mat3::Identity(), Vec3(kNaN, 0, 0), 0.1, 0.1); }),
      "p_meas"));
}

}  // namespace
}  // namespace imuconv::ceres_test
