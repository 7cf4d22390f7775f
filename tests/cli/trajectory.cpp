// imuconv run --tum / --errors: a propagate_by_preintegration task's predictions as a TUM
// trajectory and its errors against the ground truth as CSV, the same numbers as the JSON
// output's steps; and what is refused before any work.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

std::vector<std::vector<std::string>> Fields(const std::string& text, char sep) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f;
    std::istringstream l(line);
    for (std::string x; std::getline(l, x, sep);) f.push_back(x);
    rows.push_back(f);
  }
  return rows;
}

const json* Task(const json& out, const std::string& name) {
  for (const auto& t : out["tasks"])
    if (t["name"] == name) return &t;
  return nullptr;
}

TEST(Trajectory, TumAndErrorsAreTheOutputsSteps) {
  TempDir tmp;
  const std::string p = SourcePath("examples/euroc_v1_01_keyframes.json");
  const CommandResult r =
      RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(tmp.file("out.json")) + " --tum " +
                     ShellQuote(tmp.file("t.tum")) + " --errors " + ShellQuote(tmp.file("e.csv")) +
                     " --trajectory-task pred_rk4 -q",
                 tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json out = json::parse(ReadText(tmp.file("out.json")));
  const json* task = Task(out, "pred_rk4");
  ASSERT_NE(task, nullptr);
  const json& steps = (*task)["steps"];
  const auto tum = Fields(ReadText(tmp.file("t.tum")), ' ');
  const auto csv = Fields(ReadText(tmp.file("e.csv")), ',');
  ASSERT_EQ(tum.size(), steps.size());
  ASSERT_EQ(csv.size(), steps.size() + 1);
  EXPECT_EQ(csv[0], (std::vector<std::string>{"k", "t_end", "t_end_abs_ns", "position_error_m",
                                              "rotation_error_deg", "velocity_error_mps"}));
  // Both files and the JSON print each double in its shortest round-trip form, so the numbers
  // read back equal, bit for bit; the time is the absolute nanoseconds, as seconds.
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const json& s = steps[k];
    ASSERT_EQ(tum[k].size(), 8u);
    const std::int64_t ns = s["t_end_abs_ns"].get<std::int64_t>();
    EXPECT_EQ(
        tum[k][0], std::to_string(ns / 1000000000) + "." + [&] {
          std::string f = std::to_string(ns % 1000000000);
          return std::string(9 - f.size(), '0') + f;
        }());
    const json& q = s["x_e"]["q_wxyz"];
    const double expect[7] = {
        s["x_e"]["p"][0], s["x_e"]["p"][1], s["x_e"]["p"][2], q[1], q[2], q[3], q[0]};
    for (int i = 0; i < 7; ++i)
      EXPECT_EQ(std::stod(tum[k][i + 1]), expect[i]) << "step " << k << " field " << i + 1;
    const auto& e = csv[k + 1];
    ASSERT_EQ(e.size(), 6u);
    EXPECT_EQ(e[0], std::to_string(k));
    EXPECT_EQ(std::stod(e[1]), s["t_end"].get<double>());
    EXPECT_EQ(e[2], std::to_string(ns));
    EXPECT_EQ(std::stod(e[3]), s["ground_truth"]["position_error_m"].get<double>());
    EXPECT_EQ(std::stod(e[4]), s["ground_truth"]["rotation_error_deg"].get<double>());
    EXPECT_EQ(std::stod(e[5]), s["ground_truth"]["velocity_error_mps"].get<double>());
  }
}

TEST(Trajectory, RefusedBeforeAnyWork) {
  TempDir tmp;
  const std::string keyframes = SourcePath("examples/euroc_v1_01_keyframes.json");
  const std::string out = " -o " + ShellQuote(tmp.file("out.json"));
  const std::string tum = " --tum " + ShellQuote(tmp.file("t.tum"));
  CommandResult r = RunImuconv("run " + ShellQuote(keyframes) + out + tum, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err,
                  "several propagate_by_preintegration tasks ('pred_rk4', 'pred_manifold'): name "
                  "one with --trajectory-task"))
      << r.err;
  r = RunImuconv("run " + ShellQuote(keyframes) + out + tum + " --trajectory-task kf_rk4", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "no propagate_by_preintegration task named 'kf_rk4'")) << r.err;
  r = RunImuconv("run " + ShellQuote(keyframes) + out + " --tum - --trajectory-task pred_rk4", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--tum: give a file, not stdout")) << r.err;
  r = RunImuconv("run " + ShellQuote(keyframes) + out + " --tum " + ShellQuote(keyframes) +
                     " --trajectory-task pred_rk4",
                 tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "the pipeline")) << r.err;
  // The same path as the output, which does not exist yet: the same name in the same directory.
  r = RunImuconv("run " + ShellQuote(keyframes) + out + " --tum " +
                     ShellQuote(tmp.file("out.json")) + " --trajectory-task pred_rk4",
                 tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--tum " + tmp.file("out.json") + " and -o " + tmp.file("out.json") +
                             " name the same file"))
      << r.err;
  r = RunImuconv("run " + ShellQuote(keyframes) + out + tum + " --errors " +
                     ShellQuote(tmp.path() + "/./t.tum") + " --trajectory-task pred_rk4",
                 tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--errors " + tmp.path() + "/./t.tum and --tum " + tmp.file("t.tum") +
                             " name the same file"))
      << r.err;
  // A pipeline without ground truth has no errors to write.
  const std::string basics = SourcePath("examples/inline_basics.json");
  r = RunImuconv("run " + ShellQuote(basics) + out + " --errors " + ShellQuote(tmp.file("e.csv")),
                 tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "no /ground_truth") || Has(r.err, "has none")) << r.err;
  EXPECT_EQ(tmp.entries(), 0u);  // nothing was written by any of these
  // A run that fails leaves an existing trajectory file as it was.
  const std::string old = tmp.write("old.tum", "1 0 0 0 0 0 0 1\n");
  json bad = json::parse(ReadText(keyframes));
  bad["tasks"][0]["keyframes"]["start"] = -5.0;  // before the data: refused after the data is read
  bad["imu"]["path"] = SourcePath("examples/") + bad["imu"]["path"].get<std::string>();
  bad["ground_truth"]["path"] =
      SourcePath("examples/") + bad["ground_truth"]["path"].get<std::string>();
  const std::string bad_file = tmp.write("bad.json", bad.dump());
  r = RunImuconv("run " + ShellQuote(bad_file) + out + " --tum " + ShellQuote(old) +
                     " --trajectory-task pred_rk4",
                 tmp);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(ReadText(old), "1 0 0 0 0 0 0 1\n");
}

}  // namespace
