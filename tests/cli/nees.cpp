// imuconv nees on the EuRoC V1_01 slice in examples/data (20.2 s at 200 Hz, vicon2gt ground truth
// at 20 Hz): the chi-square(9) figures against tables, the report's statistics recomputed here
// from the per-window NEES values it prints, the fitted factor against its definition, the exact
// 1/k^2 scaling of NEES with the noise densities, and hostile input.
//
// Every run here is a few hundred windows of at most 1 s of samples: well under a second each in
// Release, a few seconds in the sanitized -O1 build.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "euroc_slice.h"
#include "imuconv/chi_square.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;
using nlohmann::json;

// The EuRoC datasheet densities, as in examples/euroc_v1_01_keyframes.json's noise, times k.
std::string NoiseJson(double k) {
  return json{{"gyro_noise_density", k * 1.6968e-04},
              {"accel_noise_density", k * 2.0e-3},
              {"gyro_random_walk", k * 1.9393e-05},
              {"accel_random_walk", k * 3.0e-3}}
      .dump();
}

CommandResult Nees(const std::string& args, const TempDir& tmp) {
  return RunImuconv("nees " + args, tmp);
}

std::string DataArgs(const std::string& noise_path) {
  return "--imu " + ShellQuote(kEurocSliceImu) + " --ground-truth " +
         ShellQuote(kEurocSliceGroundTruth) + " --noise " + ShellQuote(noise_path);
}

// The median and the q-quantile recomputed independently of apps/nees/order_statistics.h: a full
// sort, the two middle values for an even count, and for q the rank (n - 1) q interpolated
// linearly (the definition the schema documents).
double MedianOf(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
double QuantileOf(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double h = (v.size() - 1) * q;
  const std::size_t i = static_cast<std::size_t>(h);
  return i + 1 < v.size() ? v[i] + (h - i) * (v[i + 1] - v[i]) : v.back();
}

// ---- the chi-square figures, against printed tables (e.g. Abramowitz and Stegun table 26.8,
// NIST/SEMATECH e-Handbook 1.3.6.7.4), which give 3 decimals for these quantiles and 4-5
// significant digits for the median: the tolerances are half a unit of the last digit given ----
TEST(NeesChiSquare, QuantilesMatchTables) {
  const auto ChiSquareQuantile = [](double dof, double p) {
    return ChiSquareQuantileExact(dof, p);
  };
  EXPECT_NEAR(ChiSquareQuantile(9, 0.025), 2.700, 5e-4);
  EXPECT_NEAR(ChiSquareQuantile(9, 0.975), 19.023, 5e-4);
  EXPECT_NEAR(ChiSquareQuantile(9, 0.5), 8.343, 5e-4);
  EXPECT_NEAR(ChiSquareQuantile(1, 0.95), 3.841, 5e-4);
  EXPECT_NEAR(ChiSquareQuantile(30, 0.975), 46.979, 5e-4);
  EXPECT_NEAR(ChiSquareQuantile(100, 0.99), 135.807, 5e-4);
  // Closed forms: dof 2 is the exponential, CDF 1 - exp(-x/2); the quantile is bisected to one
  // ulp, and the CDF's series sums to double precision, so a few ulps of 1e-15 relative.
  for (double p : {0.01, 0.3, 0.5, 0.9, 0.999})
    EXPECT_NEAR(ChiSquareQuantile(2, p), -2 * std::log1p(-p), 1e-13 * (1 - 2 * std::log1p(-p)))
        << p;
  // The continued-fraction branch (x > a + 1) against the same closed form.
  EXPECT_NEAR(ChiSquareCdf(2, 40.0), 1 - std::exp(-20.0), 1e-15);
}

// ---- the report on the slice ----
class NeesSlice : public ::testing::TestWithParam<std::string> {};

TEST_P(NeesSlice, StatisticsAndFactorFromTheValuesItPrints) {
  TempDir tmp;
  const std::string noise = tmp.write("noise.json", NoiseJson(1.0));
  const json doc = RunImuconvJson(
      "nees", DataArgs(noise) + " --windows 0.2,0.5,1.0 --method " + GetParam(), tmp);
  ASSERT_TRUE(doc.is_object());
  EXPECT_EQ(doc["method"], GetParam());
  EXPECT_EQ(doc["convention"], "left");
  const double chi2_median = doc["chi2"]["median"];
  EXPECT_NEAR(chi2_median, 8.343, 5e-4);  // tables, as above
  EXPECT_NEAR(doc["chi2"]["lower"].get<double>(), 2.700, 5e-4);
  EXPECT_NEAR(doc["chi2"]["upper"].get<double>(), 19.023, 5e-4);
  const double t_begin = doc["span"][0], t_end = doc["span"][1];
  // The slice: IMU data and ground truth from the same first stamp to the same last one,
  // 1403715313462142976 - 1403715293262142976 ns = 20.2 s (the stamps are exact integers).
  EXPECT_EQ(t_begin, 0.0);
  EXPECT_NEAR(t_end, 20.2, 1e-9);
  const double lengths[] = {0.2, 0.5, 1.0};
  ASSERT_EQ(doc["windows"].size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const json& w = doc["windows"][i];
    SCOPED_TRACE(w["length"].dump());
    EXPECT_EQ(w["length"].get<double>(), lengths[i]);
    EXPECT_EQ(w["stride"].get<double>(), lengths[i]);  // default: non-overlapping
    const std::vector<double> nees = w["nees"], t_start = w["t_start"];
    // Every start t_begin + j L whose window ends inside the span (1 ns of slack for rounding).
    const std::size_t expected_count =
        static_cast<std::size_t>(std::floor((t_end - t_begin + 1e-9) / lengths[i]));
    EXPECT_EQ(w["count"].get<std::size_t>(), expected_count);
    ASSERT_EQ(nees.size(), expected_count);
    ASSERT_EQ(t_start.size(), expected_count);
    for (std::size_t j = 0; j < t_start.size(); ++j)
      EXPECT_EQ(t_start[j], t_begin + j * lengths[i]);
    // The statistics recomputed from the printed values (the JSON writer prints doubles to
    // round trip, so identical inputs; 1e-12 relative allows the summation order of the mean).
    const double median = MedianOf(nees);
    EXPECT_NEAR(w["median"].get<double>(), median, 1e-12 * median);
    double sum = 0;
    for (double v : nees) sum += v;
    EXPECT_NEAR(w["mean"].get<double>(), sum / nees.size(), 1e-12 * sum / nees.size());
    EXPECT_NEAR(w["p95"].get<double>(), QuantileOf(nees, 0.95), 1e-12 * QuantileOf(nees, 0.95));
    std::size_t inside = 0;
    for (double v : nees)
      inside += v >= doc["chi2"]["lower"].get<double>() && v <= doc["chi2"]["upper"].get<double>();
    EXPECT_EQ(w["fraction_inside"].get<double>(), static_cast<double>(inside) / nees.size());
    // The factor's definition: k^2 = median NEES(1) / chi2_9 median (one division and one
    // square root apart: 1e-12 relative is a few hundred ulps).
    const double k = w["factor"];
    EXPECT_NEAR(k * k, median / chi2_median, 1e-12 * median / chi2_median);
    std::printf("%s L = %.1f s: %zu windows, median NEES %.4g, factor %.4g\n", GetParam().c_str(),
                lengths[i], nees.size(), median, k);
  }
}

INSTANTIATE_TEST_SUITE_P(Propagators, NeesSlice, ::testing::Values("rk4", "euler"));

// Scaling all four densities by 2 scales the propagated covariance by exactly 4 (zero start
// covariance, covariance linear in the noise), so every NEES is divided by 4 and every factor
// halves. Only rounding differs between the two runs: 1e-9 relative is ample and still far
// below any modelling effect.
TEST(NeesScaling, NeesScalesAsOneOverKSquared) {
  TempDir tmp;
  const std::string args = " --windows 0.2,0.5,1.0 --method rk4";
  const json one =
      RunImuconvJson("nees", DataArgs(tmp.write("n1.json", NoiseJson(1.0))) + args, tmp);
  const json two =
      RunImuconvJson("nees", DataArgs(tmp.write("n2.json", NoiseJson(2.0))) + args, tmp);
  ASSERT_TRUE(one.is_object() && two.is_object());
  for (int i = 0; i < 3; ++i) {
    const std::vector<double> a = one["windows"][i]["nees"], b = two["windows"][i]["nees"];
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t j = 0; j < a.size(); ++j)
      EXPECT_NEAR(b[j], a[j] / 4, 1e-9 * a[j] / 4) << i << " " << j;
    const double ka = one["windows"][i]["factor"], kb = two["windows"][i]["factor"];
    EXPECT_NEAR(kb, ka / 2, 1e-9 * ka / 2) << i;
  }
}

// The same densities from a Kalibr imu.yaml, a JSON noise object and a whole pipeline (its
// /noise) give the same document, bit for bit (the same four doubles reach the same code).
TEST(NeesNoiseInput, KalibrYamlJsonAndPipelineAgree) {
  TempDir tmp;
  const std::string yaml = tmp.write("imu.yaml",
                                     "accelerometer_noise_density: 2.0e-3\n"
                                     "accelerometer_random_walk: 3.0e-3\n"
                                     "gyroscope_noise_density: 1.6968e-04\n"
                                     "gyroscope_random_walk: 1.9393e-05\n"
                                     "rostopic: /imu0\n"
                                     "update_rate: 200.0\n");
  const std::string args = " --windows 0.5 --method midpoint";
  const json from_json =
      RunImuconvJson("nees", DataArgs(tmp.write("noise.json", NoiseJson(1.0))) + args, tmp);
  const json from_yaml = RunImuconvJson("nees", DataArgs(yaml) + args, tmp);
  const json from_pipeline = RunImuconvJson(
      "nees", DataArgs(SourcePath("examples/euroc_v1_01_keyframes.json")) + args, tmp);
  EXPECT_EQ(from_json, from_yaml);
  EXPECT_EQ(from_json, from_pipeline);
}

// A stride of half the window: twice the windows, and every other one is a window of the
// non-overlapping run (the same start: (2j) * 0.1 and j * 0.2 are the same double), so its NEES
// is the same number.
TEST(NeesStride, OverlappingWindowsContainTheNonOverlappingOnes) {
  TempDir tmp;
  const std::string noise = tmp.write("noise.json", NoiseJson(1.0));
  const json plain = RunImuconvJson("nees", DataArgs(noise) + " --windows 0.2 --method rk4", tmp);
  const json half =
      RunImuconvJson("nees", DataArgs(noise) + " --windows 0.2 --stride 0.1 --method rk4", tmp);
  ASSERT_TRUE(plain.is_object() && half.is_object());
  const std::vector<double> a = plain["windows"][0]["nees"], b = half["windows"][0]["nees"];
  EXPECT_EQ(half["windows"][0]["stride"].get<double>(), 0.1);
  ASSERT_GE(b.size(), 2 * a.size() - 1);
  for (std::size_t j = 0; j < a.size(); ++j) EXPECT_EQ(b[2 * j], a[j]) << j;
}

// Another chart for the same errors: forster orders its blocks [theta, p, v] and perturbs
// differently, so the labels must pick the blocks. Both charts agree to first order, so each
// NEES differs at second order, relative size about the errors themselves (here a few mm and
// mrad over 1 s): 1e-2 relative bounds it.
TEST(NeesConvention, ForsterChartGivesNearlyTheSameNees) {
  TempDir tmp;
  const std::string noise = tmp.write("noise.json", NoiseJson(1.0));
  const json left = RunImuconvJson("nees", DataArgs(noise) + " --windows 1.0 --method rk4", tmp);
  const json forster = RunImuconvJson(
      "nees", DataArgs(noise) + " --windows 1.0 --method rk4 --convention forster", tmp);
  ASSERT_TRUE(left.is_object() && forster.is_object());
  const std::vector<double> a = left["windows"][0]["nees"], b = forster["windows"][0]["nees"];
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t j = 0; j < a.size(); ++j) EXPECT_NEAR(b[j], a[j], 1e-2 * a[j]) << j;
}

// ---- hostile input: exit 2, the message names the file and line, the pointer or the option ----
TEST(NeesHostile, UnusableInputIsRefusedByName) {
  TempDir tmp;
  const std::string noise = tmp.write("noise.json", NoiseJson(1.0));
  const std::string rest = " --windows 0.2 --method rk4";

  // Missing IMU file.
  const std::string missing = tmp.file("no_such_imu.csv");
  CommandResult r =
      Nees("--imu " + ShellQuote(missing) + " --ground-truth " +
               ShellQuote(kEurocSliceGroundTruth) + " --noise " + ShellQuote(noise) + rest,
           tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "no_such_imu.csv")) << r.err;

  // A malformed line in the IMU file (line 6: the header, then 4 good rows) and in the ground
  // truth (line 3: a row with 16 fields).
  std::ifstream imu_in(kEurocSliceImu);
  std::string imu_text, line;
  for (int i = 0; std::getline(imu_in, line); ++i)
    imu_text += (i == 5 ? "1403715293287142912,0.1,0.2,abc,1,2,3" : line) + "\n";
  const std::string bad_imu = tmp.write("bad_imu.csv", imu_text);
  r = Nees("--imu " + ShellQuote(bad_imu) + " --ground-truth " +
               ShellQuote(kEurocSliceGroundTruth) + " --noise " + ShellQuote(noise) + rest,
           tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "bad_imu.csv:6")) << r.err;
  std::ifstream gt_in(kEurocSliceGroundTruth);
  std::string gt_text;
  for (int i = 0; std::getline(gt_in, line); ++i)
    gt_text += (i == 2 ? line.substr(0, line.rfind(',')) : line) + "\n";
  const std::string bad_gt = tmp.write("bad_gt.csv", gt_text);
  r = Nees("--imu " + ShellQuote(kEurocSliceImu) + " --ground-truth " + ShellQuote(bad_gt) +
               " --noise " + ShellQuote(noise) + rest,
           tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "bad_gt.csv:3")) << r.err;

  // A window longer than the data; a non-positive window.
  r = Nees(DataArgs(noise) + " --windows 0.2,50 --method rk4", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--windows") && Has(r.err, "longer")) << r.err;
  r = Nees(DataArgs(noise) + " --windows 0 --method rk4", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--windows")) << r.err;

  // Unknown method, unknown convention, a preintegrator given as the method.
  r = Nees(DataArgs(noise) + " --windows 0.2 --method no_such_method", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--method") && Has(r.err, "no_such_method") && Has(r.err, "rk4")) << r.err;
  r = Nees(DataArgs(noise) + rest + " --convention no_such_chart", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--convention") && Has(r.err, "no_such_chart")) << r.err;
  r = Nees(DataArgs(noise) + " --windows 0.2 --method manifold", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--method")) << r.err;

  // Noise: a negative density (its JSON pointer), a missing key, all zero, a malformed YAML.
  json neg = json::parse(NoiseJson(1.0));
  neg["accel_noise_density"] = -1.0;
  r = Nees(DataArgs(tmp.write("neg.json", neg.dump())) + rest, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "neg.json") && Has(r.err, "/accel_noise_density")) << r.err;
  json missing_key = json::parse(NoiseJson(1.0));
  missing_key.erase("gyro_random_walk");
  r = Nees(DataArgs(tmp.write("missing.json", missing_key.dump())) + rest, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "missing.json") && Has(r.err, "gyro_random_walk")) << r.err;
  r = Nees(DataArgs(tmp.write("zero.json", NoiseJson(0.0))) + rest, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--noise") && Has(r.err, "all four densities are zero")) << r.err;
  r = Nees(DataArgs(tmp.write("bad.yaml", "accelerometer_noise_density: [1, 2\n")) + rest, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "bad.yaml")) << r.err;

  // Nothing on stdout for any refusal.
  EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace
