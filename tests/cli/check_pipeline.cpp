// imuconv check --pipeline and the pipeline's check task: the same samples given as a reference
// case and as a pipeline's generic CSV (another column order, milliseconds, ';') must give the
// same verdict, the same explanations and the same differences; the check task inside
// `imuconv run` must write what `check --json` prints and make the run exit 1 when inconsistent;
// hostile inputs are refused by file and pointer.
//
// Tolerance of the numbers compared between --case and --pipeline: 1e-9 on each max d / mean d
// (and the findings compared with their numbers masked). The CSV holds each time in
// milliseconds with 17 significant digits; read back and divided by 1000 it may differ from the
// case's time by a rounding of ~1e-13 s at t = 640 s, which is 2e-11 of a 5 ms step: measured,
// the d's move by up to 1.5e-11 (J_bias, aggressive-1). 1e-9 is well above that and far below
// check's verdict tolerance of 1e-2.
#include <gtest/gtest.h>

#include <cstdio>
#include <regex>
#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "gtsam_measurement.h"
#include "imuconv_test.h"
#include "number_text.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;
using nlohmann::json;

/// The same with its covariance doubled: inconsistent (off by 1 on the correlation scale).
json DoubledCov(json m) {
  for (auto& row : m["cov"]["matrix"])
    for (auto& x : row) x = 2.0 * x.get<double>();
  return m;
}

/// A case's samples as a generic CSV: header "time_ms;az;ay;ax;wz;wy;wx", times in ms.
std::string CaseCsv(const json& c) {
  std::string s = "time_ms;az;ay;ax;wz;wy;wx\n";
  for (const auto& r : c["imu"]) {
    s += Num17(r[0].get<double>() * 1000.0);
    for (int k : {6, 5, 4, 3, 2, 1}) s += ";" + Num17(r[k].get<double>());
    s += "\n";
  }
  return s;
}

/// A pipeline reading that CSV (columns by header name, time origin 0 so that its time axis
/// is the case's), the case's noise, and one check task of `meas_file`.
json CasePipeline(const json& c, const std::string& csv_file, const std::string& meas_file) {
  return {{"noise", c["noise"]},
          {"imu", CsvImuFromTimeZero(csv_file, "ms", "time_ms", ";")},
          {"tasks",
           json::array(
               {{{"type", "check"}, {"name", "chk"}, {"measurements", {{"file", meas_file}}}}})}};
}

struct CaseFiles {
  std::string meas, pipeline, case_file;
};

CaseFiles Write(const TempDir& tmp, const std::string& id, const json& measurements,
                const std::string& tag) {
  const json c = CaseJson(id);
  CaseFiles s;
  s.case_file = DataPath("reference/cases/" + id + ".json");
  s.meas = tmp.write(tag + ".meas.json", json{{"measurements", measurements}}.dump());
  const std::string csv = tmp.write(tag + ".csv", CaseCsv(c));
  s.pipeline = tmp.write(tag + ".pipeline.json", CasePipeline(c, csv, s.meas).dump(1));
  return s;
}

void ExpectSameExplanation(const json& a, const json& b, const std::string& what) {
  for (const char* key :
       {"scheme", "convention", "blocks", "jacobian_convention", "J_bias_columns", "J_bias_sign"})
    EXPECT_EQ(a[key], b[key]) << what << " " << key;
  for (const char* part : {"delta", "J_bias", "cov"})
    for (const char* stat : {"max_d", "mean_d"})
      EXPECT_NEAR(a[part][stat].get<double>(), b[part][stat].get<double>(), 1e-9)
          << what << " " << part << stat;
}

void ExpectSameCheck(const json& from_case, const json& from_pipeline, const std::string& what) {
  EXPECT_EQ(from_case["verdict"], from_pipeline["verdict"]) << what;
  EXPECT_EQ(from_case["tolerances"], from_pipeline["tolerances"]) << what;
  ASSERT_EQ(from_case["measurements"].size(), from_pipeline["measurements"].size()) << what;
  for (std::size_t i = 0; i < from_case["measurements"].size(); ++i) {
    const json& a = from_case["measurements"][i];
    const json& b = from_pipeline["measurements"][i];
    for (const char* key : {"index", "pointer", "verdict", "declared"})
      EXPECT_EQ(a[key], b[key]) << what << key;
    ASSERT_EQ(a["findings"].size(), b["findings"].size()) << what;
    // The findings' words; their numbers (max d in %.2g) are compared above.
    const std::regex number("[0-9.]+e-[0-9]+");
    for (std::size_t k = 0; k < a["findings"].size(); ++k)
      EXPECT_EQ(std::regex_replace(a["findings"][k].get<std::string>(), number, "#"),
                std::regex_replace(b["findings"][k].get<std::string>(), number, "#"))
          << what;
    EXPECT_NEAR(a["t_start"].get<double>(), b["t_start"].get<double>(), 1e-9) << what;
    EXPECT_NEAR(a["t_end"].get<double>(), b["t_end"].get<double>(), 1e-9) << what;
    ExpectSameExplanation(a["under_declaration"], b["under_declaration"],
                          what + " under_declaration");
    ExpectSameExplanation(a["best"], b["best"], what + " best");
  }
}

// ---- check --pipeline against check --case ----

TEST(CheckPipeline, SameVerdictAndNumbersAsTheCase) {
  const TempDir tmp;
  for (const char* id : {"smooth-0", "aggressive-1"}) {
    for (const bool doubled : {false, true}) {
      const json m = doubled ? DoubledCov(GtsamMeasurement(id)) : GtsamMeasurement(id);
      const std::string tag = std::string(id) + (doubled ? "-doubled" : "-plain");
      const CaseFiles s = Write(tmp, id, json::array({m}), tag);
      const CommandResult by_case = RunImuconv(
          "check " + ShellQuote(s.meas) + " --case " + ShellQuote(s.case_file) + " --json", tmp);
      const CommandResult by_pipeline = RunImuconv(
          "check " + ShellQuote(s.meas) + " --pipeline " + ShellQuote(s.pipeline) + " --json", tmp);
      ASSERT_EQ(by_case.exit_code, doubled ? 1 : 0) << tag << by_case.err;
      ASSERT_EQ(by_pipeline.exit_code, by_case.exit_code) << tag << by_pipeline.err;
      const json a = json::parse(by_case.out), b = json::parse(by_pipeline.out);
      EXPECT_EQ(b["verdict"], doubled ? "inconsistent" : "consistent") << tag;
      ExpectSameCheck(a, b, tag);
      std::printf("  %-22s verdict %s, best %s %s, max d cov: case %.3g, pipeline %.3g\n",
                  tag.c_str(), b["verdict"].get<std::string>().c_str(),
                  b["measurements"][0]["best"]["scheme"].get<std::string>().c_str(),
                  b["measurements"][0]["best"]["convention"].get<std::string>().c_str(),
                  a["measurements"][0]["best"]["cov"]["max_d"].get<double>(),
                  b["measurements"][0]["best"]["cov"]["max_d"].get<double>());
    }
  }
}

// ---- the check task inside imuconv run ----

TEST(CheckTask, RunWritesWhatCheckPrintsAndExits1WhenInconsistent) {
  const TempDir tmp;
  for (const bool doubled : {false, true}) {
    const std::string id = "smooth-0";
    const json m = doubled ? DoubledCov(GtsamMeasurement(id)) : GtsamMeasurement(id);
    const std::string tag = std::string("run-") + (doubled ? "doubled" : "plain");
    const CaseFiles s = Write(tmp, id, json::array({m}), tag);
    const std::string out = tmp.file(tag + ".out.json");
    const CommandResult run =
        RunImuconv("run -q " + ShellQuote(s.pipeline) + " -o " + ShellQuote(out), tmp);
    // 1 (exit_codes.h): the run completed and wrote its document, and a check task found an
    // inconsistency.
    ASSERT_EQ(run.exit_code, doubled ? 1 : 0) << run.err;
    if (doubled) {
      EXPECT_TRUE(Has(run.err, "check task 'chk': inconsistent")) << run.err;
    }
    const json doc = ReadJson(out);
    const json& task = doc["tasks"][0];
    EXPECT_EQ(task["type"], "check");
    EXPECT_EQ(task["name"], "chk");
    EXPECT_EQ(task["measurements_file"], s.meas);
    // The same samples read by the same readers: check --pipeline's numbers exactly.
    const CommandResult check = RunImuconv(
        "check " + ShellQuote(s.meas) + " --pipeline " + ShellQuote(s.pipeline) + " --json", tmp);
    ASSERT_EQ(check.exit_code, doubled ? 1 : 0) << check.err;
    const json c = json::parse(check.out);
    EXPECT_EQ(task["verdict"], c["verdict"]);
    EXPECT_EQ(task["tolerances"], c["tolerances"]);
    EXPECT_EQ(task["measurements"], c["measurements"]);
    // And the reference case's, within the CSV's rounding of the times.
    const CommandResult by_case = RunImuconv(
        "check " + ShellQuote(s.meas) + " --case " + ShellQuote(s.case_file) + " --json", tmp);
    ExpectSameCheck(json::parse(by_case.out), task, tag);
  }
}

TEST(CheckTask, OtherTasksNarrowingTheKeptRangeDoNotNarrowTheCheck) {
  // A propagate task over the first 0.1 s keeps only that part of the IMU data in memory; the
  // check's measurement spans the whole case, so the check task reads the samples whole.
  const TempDir tmp;
  const json c = CaseJson("smooth-0");
  const CaseFiles s = Write(tmp, "smooth-0", json::array({GtsamMeasurement("smooth-0")}), "narrow");
  json p = ReadJson(s.pipeline);
  const double t0 = c["imu"].front()[0].get<double>();
  p["tasks"].push_back(
      {{"type", "propagate"},
       {"name", "short"},
       {"propagator", "euler"},
       {"start", {{"state", {{"p", {0, 0, 0}}, {"q_wxyz", {1, 0, 0, 0}}, {"v", {0, 0, 0}}}}}},
       {"interval", {{"t_start", t0}, {"t_end", t0 + 0.1}}}});
  const std::string pipeline = tmp.write("narrow2.pipeline.json", p.dump(1));
  const std::string out = tmp.file("narrow.out.json");
  const CommandResult run =
      RunImuconv("run -q " + ShellQuote(pipeline) + " -o " + ShellQuote(out), tmp);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json doc = ReadJson(out);
  ASSERT_TRUE(doc["imu"].contains("kept_range")) << doc["imu"].dump();
  EXPECT_EQ(doc["tasks"][0]["verdict"], "consistent");
  const CommandResult by_case = RunImuconv(
      "check " + ShellQuote(s.meas) + " --case " + ShellQuote(s.case_file) + " --json", tmp);
  ExpectSameCheck(json::parse(by_case.out), doc["tasks"][0], "narrowed");
}

// ---- hostile input ----

TEST(CheckPipelineHostile, RefusedByFileAndPointer) {
  const TempDir tmp;
  const CaseFiles s =
      Write(tmp, "smooth-0", json::array({GtsamMeasurement("smooth-0")}), "hostile");
  const std::string q_meas = ShellQuote(s.meas);

  // Both sources, or none: a usage error (2), nothing checked.
  CommandResult r = RunImuconv("check " + q_meas + " --case " + ShellQuote(s.case_file) +
                                   " --pipeline " + ShellQuote(s.pipeline) + " --json",
                               tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--pipeline") && Has(r.err, "--case")) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  r = RunImuconv("check " + q_meas + " --json", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "one of --case CASE.json or --pipeline P.json")) << r.err;

  // A pipeline without /noise.
  json p = ReadJson(s.pipeline);
  p.erase("noise");
  r = RunImuconv(
      "check " + q_meas + " --pipeline " + ShellQuote(tmp.write("no_noise.json", p.dump())), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "no_noise.json") && Has(r.err, "/noise") &&
              Has(r.err, "required key is missing"))
      << r.err;
  // ... and as a run's check task: refused before any task runs, nothing written.
  const std::string out = tmp.file("never.json");
  r = RunImuconv("run -q " + ShellQuote(tmp.file("no_noise.json")) + " -o " + ShellQuote(out), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "/noise") && Has(r.err, "task 'chk'")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));

  // A CSV column that is not in the header: the CSV reader's message, with the file.
  p = ReadJson(s.pipeline);
  p["imu"]["columns"]["wx"] = "gyro_x";
  r = RunImuconv(
      "check " + q_meas + " --pipeline " + ShellQuote(tmp.write("bad_column.json", p.dump())), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "hostile.csv") && Has(r.err, "gyro_x")) << r.err;

  // A measurement outside the pipeline's samples (times on its axis: an origin shifted by 1000 s).
  p = ReadJson(s.pipeline);
  p["imu"]["time_origin"] = 1000000;  // ms
  const std::string shifted = tmp.write("shifted.json", p.dump());
  r = RunImuconv("check " + q_meas + " --pipeline " + ShellQuote(shifted), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "hostile.meas.json") && Has(r.err, "/measurements/0") &&
              Has(r.err, "not inside the pipeline's IMU samples"))
      << r.err;
  r = RunImuconv("run -q " + ShellQuote(shifted) + " -o " + ShellQuote(out), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "hostile.meas.json") && Has(r.err, "/measurements/0") &&
              Has(r.err, "not inside the IMU samples"))
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));

  // The check task's measurements as a task name, and a missing measurements file.
  p = ReadJson(s.pipeline);
  p["tasks"][0]["measurements"] = "pre";
  r = RunImuconv(
      "run -q " + ShellQuote(tmp.write("by_name.json", p.dump())) + " -o " + ShellQuote(out), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "by_name.json") && Has(r.err, "/tasks/0/measurements") &&
              Has(r.err, "expected {\"file\": PATH}"))
      << r.err;
  p["tasks"][0]["measurements"] = {{"file", "nowhere.json"}};
  r = RunImuconv(
      "run -q " + ShellQuote(tmp.write("missing.json", p.dump())) + " -o " + ShellQuote(out), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "nowhere.json")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));

  // The output may not overwrite the check's measurements file (an input of the run).
  r = RunImuconv("run -q " + ShellQuote(s.pipeline) + " -o " + q_meas, tmp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(Has(r.err, "input")) << r.err;
  EXPECT_NO_THROW(ReadJson(s.meas).at("measurements"));
}

}  // namespace
