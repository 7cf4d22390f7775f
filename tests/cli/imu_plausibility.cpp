// Plausibility warnings on IMU samples (apps/pipeline/src/data/imu_plausibility.cpp,
// docs/imu-plausibility.md): the gyro and accelerometer columns swapped, the accelerometer in
// g and the gyro in deg/s are each named, with the median magnitudes as evidence, on stderr
// (also with -q) and in --json as "warnings", by every command that reads IMU samples; the
// command still runs and exits as it would have. Correct data gives no warning.
//
// The medians quoted are checked against the test's own computation (sorted norms) printed the
// way the warning prints them ("%.4g"): the same data, so the same text.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "../pipeline/inline_pipeline.h"
#include "../pipeline/pipeline_test_util.h"
#include "euroc_slice.h"
#include "gtsam_measurement.h"
#include "imuconv_test.h"
#include "number_text.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

std::string G4(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", x);
  return b;
}

enum class Mistake { none, swapped, accel_in_g, gyro_in_deg };

// Rows [t, wx, wy, wz, ax, ay, az] of a reference case with one mistake made.
json WithMistake(json imu, Mistake m) {
  for (auto& r : imu)
    for (std::size_t k = 1; k <= 3; ++k) {
      double w = r[k].get<double>(), a = r[k + 3].get<double>();  // (a JSON 0 is an integer)
      if (m == Mistake::swapped) std::swap(w, a);
      if (m == Mistake::accel_in_g) a /= 9.80665;
      if (m == Mistake::gyro_in_deg) w *= 180.0 / M_PI;
      r[k] = w;
      r[k + 3] = a;
    }
  return imu;
}

// The median of |columns 1..3| (gyro) or |4..6| (accel): the upper middle and lower middle
// averaged for an even count, as a median is.
double MedianNorm(const json& imu, int first) {
  std::vector<double> n;
  for (const auto& r : imu)
    n.push_back(std::sqrt(std::pow(r[first].get<double>(), 2) +
                          std::pow(r[first + 1].get<double>(), 2) +
                          std::pow(r[first + 2].get<double>(), 2)));
  std::sort(n.begin(), n.end());
  const std::size_t k = n.size() / 2;
  return n.size() % 2 ? n[k] : 0.5 * (n[k - 1] + n[k]);
}

std::string Csv(const json& imu) {
  std::string s = "t,wx,wy,wz,ax,ay,az\n";
  for (const auto& r : imu) {
    s += Num17(r[0].get<double>());
    for (int k = 1; k <= 6; ++k) s += "," + Num17(r[k].get<double>());
    s += "\n";
  }
  return s;
}

// A pipeline reading the CSV and propagating with rk4 from a given state over all the samples
// (the reader keeps only the samples the tasks use, and those are what is judged).
json Pipeline(const json& c, const std::string& csv) {
  const double t0 = c["imu"].front()[0].get<double>(), t1 = c["imu"].back()[0].get<double>();
  return {{"noise", c["noise"]},
          {"imu", CsvImuFromTimeZero(csv, "s", "t")},
          {"tasks",
           {{{"type", "propagate"},
             {"name", "p"},
             {"propagator", "rk4"},
             {"state_convention", "left"},
             {"start", {{"state", RestAtOriginWithZeroBiases()}}},
             {"interval", {{"t_start", t0}, {"t_end", t1}}}}}}};
}

// The sentence expected for a mistake, up to its first number and its evidence.
std::vector<std::string> Expected(Mistake m, const json& imu) {
  const double g = MedianNorm(imu, 1), a = MedianNorm(imu, 4);
  switch (m) {
    case Mistake::none:
      return {};
    case Mistake::swapped:
      return {"the gyro and accelerometer columns look swapped: median |gyro| " + G4(g),
              "and median |accel| " + G4(a) + " (expected near 9.81 m/s^2, gravity) over " +
                  std::to_string(imu.size()) + " samples"};
    case Mistake::accel_in_g:
      return {"the accelerometer looks like it is in g, not m/s^2: median |accel| " + G4(a) +
              " over " + std::to_string(imu.size()) + " samples"};
    case Mistake::gyro_in_deg:
      return {"the gyro looks like it is in deg/s, not rad/s: median |gyro| " + G4(g),
              "(" + G4(g * 180.0 / M_PI) + " deg/s if it were rad/s; " + G4(g * M_PI / 180.0) +
                  " rad/s if it is deg/s)"};
  }
  return {};
}

const Mistake kAll[] = {Mistake::none, Mistake::swapped, Mistake::accel_in_g, Mistake::gyro_in_deg};

TEST(ImuPlausibility, RunWarnsWithTheEvidenceAndStillRuns) {
  const TempDir tmp;
  for (const char* id : {"smooth-0", "aggressive-0", "static-0"}) {
    const json c = ReadJson(DataPath(std::string("reference/cases/") + id + ".json"));
    for (const Mistake m : kAll) {
      const json imu = WithMistake(c["imu"], m);
      const std::string tag = std::string(id) + "-" + std::to_string(static_cast<int>(m));
      const std::string csv = tmp.write(tag + ".csv", Csv(imu));
      const std::string p = tmp.write(tag + ".json", Pipeline(c, csv).dump());
      // -q: warnings are kept (only summaries and "wrote" lines go).
      const CommandResult r = RunImuconv(
          "-q run " + ShellQuote(p) + " -o " + ShellQuote(tmp.file(tag + ".out.json")), tmp);
      EXPECT_EQ(r.exit_code, 0) << tag << r.err;
      // At rest (static-0) the gyro reads ~0 in any unit: only the accelerometer's mistakes show.
      const bool visible = !(std::string(id) == "static-0" && m == Mistake::gyro_in_deg);
      const std::vector<std::string> want = visible ? Expected(m, imu) : std::vector<std::string>{};
      if (want.empty()) {
        EXPECT_FALSE(Has(r.err, "warning")) << tag << r.err;
        continue;
      }
      EXPECT_TRUE(Has(r.err, "warning: " + csv + ": ")) << tag << r.err;
      for (const auto& w : want)
        EXPECT_TRUE(Has(r.err, w)) << tag << "\nwant: " << w << "\n" << r.err;
      // One mistake, one warning.
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << tag << r.err;
    }
  }
}

TEST(ImuPlausibility, CheckPutsTheWarningsInItsJson) {
  const TempDir tmp;
  const json c = ReadJson(DataPath("reference/cases/smooth-0.json"));
  const json meas = {{"measurements", {GtsamMeasurement("smooth-0")}}};
  const std::string mf = tmp.write("meas.json", meas.dump());
  for (const Mistake m : kAll) {
    json bad = c;
    bad["imu"] = WithMistake(c["imu"], m);
    const std::string cf =
        tmp.write("case" + std::to_string(static_cast<int>(m)) + ".json", bad.dump());
    const CommandResult r =
        RunImuconv("check " + ShellQuote(mf) + " --case " + ShellQuote(cf) + " --json", tmp);
    // A warning is not an error: the check is judged (0 or 1), never refused (2).
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.exit_code << r.err;
    const json out = json::parse(r.out);
    const std::vector<std::string> want = Expected(m, bad["imu"]);
    if (want.empty()) {
      EXPECT_FALSE(out.contains("warnings")) << out["warnings"];
      EXPECT_EQ(r.exit_code, 0) << r.err;  // GTSAM's own numbers on the true samples
      continue;
    }
    ASSERT_TRUE(out.contains("warnings")) << r.out;
    ASSERT_EQ(out["warnings"].size(), 1u) << out["warnings"];
    const std::string w = out["warnings"][0];
    EXPECT_TRUE(Has(w, cf + ": ")) << w;
    for (const auto& piece : want) EXPECT_TRUE(Has(w, piece)) << piece << "\n" << w;
    EXPECT_TRUE(Has(r.err, "imuconv: warning: " + w)) << r.err;
  }
}

TEST(ImuPlausibility, NeesOnSwappedColumnsWarns) {
  // The EuRoC slice through a pipeline whose column map swaps the gyro and the accelerometer:
  // nees fits a factor in the thousands and exits 0, as before, but now says why.
  const TempDir tmp;
  for (const bool swapped : {false, true}) {
    const json cols =
        swapped ? json{{"t", 0}, {"wx", 4}, {"wy", 5}, {"wz", 6}, {"ax", 1}, {"ay", 2}, {"az", 3}}
                : json{{"t", 0}, {"wx", 1}, {"wy", 2}, {"wz", 3}, {"ax", 4}, {"ay", 5}, {"az", 6}};
    const json p = NeesPipeline({{"format", "csv"},
                                 {"path", kEurocSliceImu},
                                 {"comment", "#"},
                                 {"time_unit", "ns"},
                                 {"columns", cols}});
    const std::string pf = tmp.write(swapped ? "swapped.json" : "plain.json", p.dump());
    const CommandResult r =
        RunImuconv("nees --pipeline " + ShellQuote(pf) + " --windows 1 --method rk4 --json", tmp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json out = json::parse(r.out);
    if (!swapped) {
      EXPECT_FALSE(out.contains("warnings")) << out["warnings"];
      EXPECT_FALSE(Has(r.err, "warning")) << r.err;
      continue;
    }
    ASSERT_TRUE(out.contains("warnings")) << r.out;
    EXPECT_TRUE(Has(out["warnings"][0].get<std::string>(),
                    "the gyro and accelerometer columns look swapped"))
        << out["warnings"];
    EXPECT_TRUE(Has(r.err, "imuconv: warning: ")) << r.err;
  }
}

}  // namespace
