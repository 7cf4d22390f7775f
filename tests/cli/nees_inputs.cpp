// imuconv nees --pipeline: the EuRoC V1_01 slice (examples/data) rewritten here as a generic CSV
// (another column order, times in microseconds with a fraction, ';' and a header, columns by
// name and by index), read through a pipeline's column map with the slice's ground truth and
// noise, must give the NEES of every window that the EuRoC files give; a Kalibr imu.yaml as
// --noise replaces the pipeline's noise; hostile pipelines are refused by file and pointer.
//
// Tolerance between the two readings: 1e-9 relative on every NEES. The microsecond stamps are
// the nanosecond ones with a decimal point put in (the same digits), so the relative times agree
// to the rounding of the fraction, ~1e-16 s relative to 20 s; a window's error vector (~mm) moves
// by about v * 1e-16 s, a relative change of NEES far below 1e-12. 1e-9 is well above that and
// would catch any real difference (a sample shifted by one period changes NEES by percents).
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "euroc_slice.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;
using nlohmann::json;

const std::string kKalibr = DataPath("kalibr/euroc_imu.yaml");

std::vector<std::string> Split(const std::string& line, char sep) {
  std::vector<std::string> f;
  std::size_t at = 0;
  for (std::size_t next; (next = line.find(sep, at)) != std::string::npos; at = next + 1)
    f.push_back(line.substr(at, next - at));
  f.push_back(line.substr(at));
  return f;
}

/// The EuRoC IMU file as "gz;gy;gx;time_us;az;ay;ax" rows: the same digits, times in us.
std::string GenericCsv() {
  std::string out = "gz;gy;gx;time_us;az;ay;ax\n";
  std::size_t rows = 0;
  for (const std::string& line : Split(ReadText(kEurocSliceImu), '\n')) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f = Split(line, ',');
    EXPECT_EQ(f.size(), 7u) << line;
    if (!f.back().empty() && f.back().back() == '\r') f.back().pop_back();
    const std::string ns = f[0];
    const std::string us = ns.substr(0, ns.size() - 3) + "." + ns.substr(ns.size() - 3);
    out += f[3] + ";" + f[2] + ";" + f[1] + ";" + us + ";" + f[6] + ";" + f[5] + ";" + f[4] + "\n";
    ++rows;
  }
  EXPECT_GT(rows, 4000u);  // 20.2 s at 200 Hz
  return out;
}

json GenericPipeline(const std::string& csv) {
  return NeesPipeline({{"format", "csv"},
                       {"path", csv},
                       {"delimiter", ";"},
                       {"header_rows", 1},
                       {"time_unit", "us"},
                       {"columns",
                        {{"t", "time_us"},
                         {"wx", 2},
                         {"wy", 1},
                         {"wz", 0},
                         {"ax", "ax"},
                         {"ay", "ay"},
                         {"az", 4}}}});
}

void ExpectSameNees(const json& a, const json& b) {
  ASSERT_EQ(a["windows"].size(), b["windows"].size());
  for (std::size_t w = 0; w < a["windows"].size(); ++w) {
    const json &x = a["windows"][w], &y = b["windows"][w];
    ASSERT_EQ(x["nees"].size(), y["nees"].size()) << w;
    ASSERT_GT(x["nees"].size(), 10u);
    for (std::size_t i = 0; i < x["nees"].size(); ++i) {
      const double u = x["nees"][i].get<double>(), v = y["nees"][i].get<double>();
      EXPECT_NEAR(u, v, 1e-9 * std::abs(u)) << "window length " << w << ", window " << i;
      EXPECT_NEAR(x["t_start"][i].get<double>(), y["t_start"][i].get<double>(), 1e-9);
    }
    EXPECT_NEAR(x["factor"].get<double>(), y["factor"].get<double>(),
                1e-9 * x["factor"].get<double>());
  }
}

TEST(NeesPipelineInput, GenericCsvGivesTheNeesOfTheEurocFiles) {
  const TempDir tmp;
  const std::string noise = tmp.write("noise.json", kEurocNoise.dump());
  const std::string csv = tmp.write("imu_generic.csv", GenericCsv());
  const std::string pipeline = tmp.write("generic.json", GenericPipeline(csv).dump(1));
  const std::string common = " --windows 0.5,1.0 --method rk4";
  const json euroc = RunImuconvJson("nees",
                                    "--imu " + ShellQuote(kEurocSliceImu) + " --ground-truth " +
                                        ShellQuote(kEurocSliceGroundTruth) + " --noise " +
                                        ShellQuote(noise) + common,
                                    tmp);
  const json generic = RunImuconvJson("nees", "--pipeline " + ShellQuote(pipeline) + common, tmp);
  ExpectSameNees(euroc, generic);
  std::printf("  %zu + %zu windows; factor at 0.5 s: EuRoC %.12g, generic CSV %.12g\n",
              euroc["windows"][0]["nees"].size(), euroc["windows"][1]["nees"].size(),
              euroc["windows"][0]["factor"].get<double>(),
              generic["windows"][0]["factor"].get<double>());
  // --noise replaces the pipeline's: a Kalibr imu.yaml of the same densities, and a JSON noise
  // object of twice them (NEES / 4, the exact 1/k^2 scaling: 1e-12 relative, round-off).
  ExpectSameNees(euroc, RunImuconvJson("nees",
                                       "--pipeline " + ShellQuote(pipeline) + " --noise " +
                                           ShellQuote(kKalibr) + common,
                                       tmp));
  json twice = kEurocNoise;
  for (auto& v : twice) v = 2.0 * v.get<double>();
  const json doubled =
      RunImuconvJson("nees",
                     "--pipeline " + ShellQuote(pipeline) + " --noise " +
                         ShellQuote(tmp.write("twice.json", twice.dump())) + common,
                     tmp);
  ASSERT_EQ(doubled["windows"][0]["nees"].size(), euroc["windows"][0]["nees"].size());
  for (std::size_t i = 0; i < doubled["windows"][0]["nees"].size(); ++i)
    EXPECT_NEAR(doubled["windows"][0]["nees"][i].get<double>() * 4.0,
                euroc["windows"][0]["nees"][i].get<double>(),
                1e-12 * euroc["windows"][0]["nees"][i].get<double>());
}

TEST(NeesPipelineInput, HostilePipelinesAreRefusedByName) {
  const TempDir tmp;
  const std::string csv = tmp.write("imu_generic.csv", GenericCsv());
  const std::string common = " --windows 0.5 --method rk4";
  json p = GenericPipeline(csv);

  // --pipeline with --imu: a usage error.
  CommandResult r = RunImuconv("nees --pipeline " + ShellQuote(tmp.write("ok.json", p.dump())) +
                                   " --imu " + ShellQuote(kEurocSliceImu) + common,
                               tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--pipeline") && Has(r.err, "--imu")) << r.err;
  // Neither.
  r = RunImuconv("nees" + common, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--pipeline P.json")) << r.err;

  // nees on the pipeline `doc`, written to the file `name`.
  const auto nees_on = [&](const std::string& name, const json& doc) {
    return RunImuconv("nees --pipeline " + ShellQuote(tmp.write(name, doc.dump())) + common, tmp);
  };
  // ... is refused (exit 2), its message naming the file and saying each of `says`.
  const auto expect_refused = [&](const std::string& name, const json& doc,
                                  std::initializer_list<const char*> says) {
    const CommandResult refused = nees_on(name, doc);
    EXPECT_EQ(refused.exit_code, 2) << name;
    bool says_all = Has(refused.err, name);
    for (const char* s : says) says_all = says_all && Has(refused.err, s);
    EXPECT_TRUE(says_all) << refused.err;
  };

  // No ground truth; pose-only ground truth; no noise and no --noise.
  json q = p;
  q.erase("ground_truth");
  q["tasks"][0]["start"] = {
      {"state", {{"p", {0, 0, 0}}, {"q_wxyz", {1, 0, 0, 0}}, {"v", {0, 0, 0}}}}};
  expect_refused("no_gt.json", q, {"/ground_truth", "required key is missing"});
  q = p;
  q["ground_truth"] = {{"format", "euroc_pose"},
                       {"path", DataPath("pipeline_cases/files/vicon0.csv")}};
  expect_refused("poses.json", q, {"/ground_truth/format", "full state"});
  q = p;
  q.erase("noise");
  expect_refused("no_noise.json", q, {"/noise"});

  // A time unit that makes the microsecond stamps seconds: the pipeline's timing check.
  q = p;
  q["imu"]["time_unit"] = "s";
  r = nees_on("unit.json", q);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "imu_generic.csv")) << r.err;
  EXPECT_TRUE(r.out.empty());
}

}  // namespace
