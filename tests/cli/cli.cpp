// The imuconv binary: each subcommand's output, exit codes and error messages.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv/kernels/preintegration.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

TEST(Cli, HelpEverywhere) {
  TempDir tmp;
  CommandResult r = RunImuconv("--help", tmp);
  EXPECT_EQ(r.exit_code, 0);
  for (const char* sub : {"plugins", "convert", "conversion", "run", "--plugin-dir"})
    EXPECT_TRUE(Has(r.out, sub)) << sub << "\n" << r.out;
  for (const char* sub : {"plugins", "convert", "conversion", "run"}) {
    r = RunImuconv(std::string(sub) + " --help", tmp);
    EXPECT_EQ(r.exit_code, 0) << sub;
    EXPECT_TRUE(Has(r.out, "--plugin-dir")) << sub << "\n" << r.out;
  }
}

TEST(Cli, VersionNamesTheReleaseAndThePluginAbi) {
  TempDir tmp;
  const CommandResult r = RunImuconv("--version", tmp);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, std::string("imuconv ") + IMUCONV_PROJECT_VERSION + " (plugin ABI " +
                       std::to_string(imuconv::kPluginAbiVersion) + ")\n");
}

TEST(Cli, UsageErrorsExitWith2) {
  TempDir tmp;
  CommandResult r = RunImuconv("", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "A subcommand is required")) << r.err;
  r = RunImuconv("frobnicate", tmp);
  EXPECT_EQ(r.exit_code, 2);
  r = RunImuconv("run", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "pipeline is required")) << r.err;
  r = RunImuconv("conversion --from left", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--to is required")) << r.err;
}

TEST(Cli, PluginsTableAndJson) {
  TempDir tmp;
  CommandResult r = RunImuconv("plugins", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* s :
       {"state_convention:", "preint_convention:", "propagator:", "preintegrator:", "rk4",
        "gtsam_manifold", "[theta,p,v,ba,bg]", "imuconv_plugin_state_left.so", "1.0.0"})
    EXPECT_TRUE(Has(r.out, s)) << s << "\n" << r.out;
  EXPECT_FALSE(Has(r.out, "load errors:"));

  r = RunImuconv("plugins --json", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_TRUE(j["load_errors"].empty());
  // The same plugins as the test registry, with the same block orders.
  const auto& reg = Plugins();
  EXPECT_EQ(j["plugins"].size(), reg.plugins().size());
  for (const auto& p : j["plugins"]) {
    for (const char* k : {"id", "kind", "file", "version", "blocks"})
      EXPECT_TRUE(p.contains(k)) << p.dump();
    if (p["kind"] == "state_convention") {
      EXPECT_EQ(p["blocks"].get<std::vector<std::string>>(),
                reg.info(imuconv::PluginKind::StateConvention, p["id"].get<std::string>()).blocks);
    }
  }
}

TEST(Cli, PluginDirIsSearchedFirstAndLoadErrorsAreListed) {
  TempDir tmp;
  fs::create_directories(tmp.file("extra"));
  const std::string broken = tmp.write("extra/imuconv_plugin_broken.so", "not a shared object\n");
  for (const std::string& args :
       {"plugins --json --plugin-dir " + ShellQuote(tmp.file("extra")),
        "--plugin-dir " + ShellQuote(tmp.file("extra")) + " plugins --json"}) {
    const CommandResult r = RunImuconv(args, tmp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json j = json::parse(r.out);
    ASSERT_FALSE(j["search_path"].empty());
    EXPECT_EQ(j["search_path"][0], tmp.file("extra"));
    ASSERT_EQ(j["load_errors"].size(), 1u) << r.out;
    EXPECT_EQ(j["load_errors"][0]["file"], broken);
    EXPECT_TRUE(Has(j["load_errors"][0]["message"], "cannot load")) << r.out;
    EXPECT_GT(j["plugins"].size(), 5u);  // the built-in ones still load
  }
  const CommandResult t = RunImuconv("plugins --plugin-dir " + ShellQuote(tmp.file("extra")), tmp);
  EXPECT_TRUE(Has(t.out, "load errors:\n  " + broken + ": ")) << t.out;
}

TEST(Cli, ConversionMatchesTheRegistry) {
  TempDir tmp;
  const std::string state = SourcePath("examples/hover.state.json");
  CommandResult r = RunImuconv(
      "conversion --from left --to gtsam_navstate --state " + ShellQuote(state) + " --json", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["jacobian"]["rows"]["convention"], "gtsam_navstate");
  EXPECT_EQ(j["jacobian"]["rows"]["blocks"], json({"theta", "p", "v", "ba", "bg"}));
  EXPECT_EQ(j["jacobian"]["cols"]["convention"], "left");
  EXPECT_EQ(j["jacobian"]["cols"]["blocks"], json({"p", "theta", "v", "bg", "ba"}));
  const imuconv::ImuState x = imuconv::pipeline::ReadStateFile(state);
  const imuconv::Mat15 expect = Plugins().conversion("left", "gtsam_navstate", x);
  // Same computation, printed with 17 significant digits: equal to 1e-15.
  EXPECT_LT((JsonMatrix(j["jacobian"]["matrix"]) - expect).cwiseAbs().maxCoeff(), 1e-15);

  r = RunImuconv("conversion --from left --to gtsam_navstate --state " + ShellQuote(state), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Has(r.out, "rows: gtsam_navstate blocks, columns: left blocks")) << r.out;
  EXPECT_TRUE(Has(r.out, "theta.x")) << r.out;
  EXPECT_TRUE(Has(r.out, "\nbg.z ")) << r.out;
  EXPECT_TRUE(Has(r.out, "         p.x         p.y         p.z     theta.x")) << r.out;
}

TEST(Cli, ConversionErrors) {
  TempDir tmp;
  const std::string state = SourcePath("examples/hover.state.json");
  CommandResult r =
      RunImuconv("conversion --from left --to navstate --state " + ShellQuote(state), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "imuconv: error: unknown state convention 'navstate'; known: ")) << r.err;
  r = RunImuconv("conversion --from gtsam_manifold --to left --state " + ShellQuote(state), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "('gtsam_manifold' is an increment convention)")) << r.err;
  const std::string bad = tmp.write(
      "bad.state.json", R"({"p": [0, 0, 0], "q_wxyz": [1, 0, 0], "v": [0, 0, 0], "w": 1})");
  r = RunImuconv("conversion --from left --to gtsam_navstate --state " + ShellQuote(bad), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, bad + ": /q_wxyz: expected an array of 4 numbers, found an array of 3"))
      << r.err;
  EXPECT_TRUE(Has(r.err, bad + ": /w: unknown key 'w'")) << r.err;
  r = RunImuconv(
      "conversion --from left --to gtsam_navstate --state " + ShellQuote(tmp.file("none.json")),
      tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, tmp.file("none.json") + ": cannot open the file for reading")) << r.err;
}

// A table of 200 steps: by default its totals and the worst steps, which must be exactly the
// rows with the 5 largest position and the 5 largest rotation errors of the full table.
TEST(Cli, LongStepTablesShowTheWorstSteps) {
  TempDir tmp;
  const std::string p = SourcePath("examples/euroc_v1_01_keyframes.json");
  const CommandResult full = RunImuconv(
      "run " + ShellQuote(p) + " -o " + ShellQuote(tmp.file("a.json")) + " --table", tmp);
  const CommandResult brief =
      RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(tmp.file("b.json")), tmp);
  ASSERT_EQ(full.exit_code, 0) << full.err;
  ASSERT_EQ(brief.exit_code, 0) << brief.err;
  EXPECT_EQ(ReadText(tmp.file("a.json")),
            ReadText(tmp.file("b.json")));  // the output does not change
  // The first step table of each summary: rows are lines that start with a right-aligned index.
  const auto rows_of = [](const std::string& text) {
    std::vector<std::string> rows;
    std::istringstream in(text.substr(text.find("propagate_by_preintegration")));
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line) && line.find(" total (") != 0)
      if (line.size() > 6 && line[5] >= '0' && line[5] <= '9') rows.push_back(line);
    return rows;
  };
  const auto all = rows_of(full.out);
  ASSERT_EQ(all.size(), 200u) << full.out;
  EXPECT_TRUE(Has(brief.out,
                  "200 steps: the totals and the worst steps against the ground truth (--table "
                  "prints every row)"))
      << brief.out;
  const std::string after = brief.out.substr(brief.out.find("worst steps (the 5 largest"));
  std::vector<std::string> shown;
  std::istringstream in(after);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line) && line.size() > 6 && line[5] >= '0' && line[5] <= '9')
    shown.push_back(line);
  // Expected: from the full table, the indices of the 5 largest of each error column.
  const auto column = [](const std::string& row, int from_end) {
    std::istringstream r(row);
    std::vector<double> v;
    double x;
    while (r >> x) v.push_back(x);
    return v[v.size() - static_cast<std::size_t>(from_end)];
  };
  std::set<std::size_t> expect;
  for (int col : {2, 1}) {  // pos.err, rot.err
    std::vector<std::size_t> idx(all.size());
    std::iota(idx.begin(), idx.end(), 0);
    std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
      return column(all[a], col) > column(all[b], col);
    });
    expect.insert(idx.begin(), idx.begin() + 5);
  }
  std::vector<std::string> expect_rows;
  for (std::size_t k : expect) expect_rows.push_back(all[k]);
  EXPECT_EQ(shown, expect_rows) << brief.out;
  EXPECT_LT(brief.out.size(), full.out.size() / 4);
}

TEST(Cli, RunWritesOutputAndSummary) {
  TempDir tmp;
  const std::string out = tmp.file("out.json");
  CommandResult r = RunImuconv(
      "run " + ShellQuote(SourcePath("examples/inline_basics.json")) + " -o " + ShellQuote(out),
      tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Has(r.out, "propagate_by_preintegration 'by_preint'")) << r.out;
  EXPECT_TRUE(Has(r.out, "wrote " + out)) << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const json j = json::parse(ReadText(out));
  EXPECT_EQ(j["tasks"].size(), 10u);
  EXPECT_GT(CheckMatricesLabelled(j), 0u);

  // -o -: the JSON alone on stdout, the summary on stderr.
  r = RunImuconv("run " + ShellQuote(SourcePath("examples/inline_basics.json")) + " -o -", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["tasks"].size(), 10u);
  EXPECT_TRUE(Has(r.err, "preintegrate 'kf'")) << r.err;
}

TEST(Cli, RunReportsEveryConfigErrorWithItsPointer) {
  TempDir tmp;
  json doc = json::parse(ReadText(SourcePath("examples/inline_basics.json")));
  doc["tasks"][0]["propagatr"] = "rk4";
  doc["tasks"][1]["keyframes"][2] = "late";
  doc.erase("noise");
  const std::string f = tmp.write("bad.json", doc.dump(2));
  const CommandResult r =
      RunImuconv("run " + ShellQuote(f) + " -o " + ShellQuote(tmp.file("o.json")), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "imuconv: error: " + f + ": ")) << r.err;
  EXPECT_TRUE(Has(r.err, f + ": /noise: required key is missing")) << r.err;
  EXPECT_TRUE(Has(r.err, f + ": /tasks/0/propagatr: unknown key 'propagatr'")) << r.err;
  EXPECT_TRUE(Has(r.err, f + ": /tasks/1/keyframes/2: expected a number, found a string")) << r.err;
  EXPECT_FALSE(fs::exists(tmp.file("o.json")));
}

TEST(Cli, RunReportsBadDataWithFileAndLine) {
  TempDir tmp;
  fs::create_directories(tmp.file("data"));
  tmp.write(
      "data/imu.csv",
      "#timestamp "
      "[ns],w_x,w_y,w_z,a_x,a_y,a_z\n1000,0,0,0,0,0,9.8\n2000,0,0,0,0,0,9.8\n1500,0,0,0,0,0,9.8\n");
  json doc = json::parse(ReadText(SourcePath("examples/euroc_v1_01_keyframes.json")));
  doc["imu"]["path"] = "data/imu.csv";
  doc.erase("ground_truth");
  doc["tasks"] = {{{"type", "preintegrate"},
                   {"name", "p"},
                   {"method", {{"propagator", "rk4"}}},
                   {"interval", {{"t_start", 0.0}, {"t_end", 1e-6}}}}};
  const std::string f = tmp.write("p.json", doc.dump());
  const CommandResult r = RunImuconv("run " + ShellQuote(f) + " -o -", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, tmp.file("data/imu.csv") +
                             ":4: timestamp 1500 is not after the previous sample's (line 3)"))
      << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

// `imuconv bench` runs the benchmark set of bench/ from the tool. Speed is never asserted
// (bench/README.md keeps the figures); this checks that every benchmark of the set (the
// integrators, the two schemes, a conversion, the plugin overhead, and one per compiled kernel
// instance the CPU runs) is there and ran: a positive, finite rate in
// IMU samples per second, in a JSON report that parses, with no plugin load errors.
TEST(Cli, BenchRunsTheWholeSet) {
  TempDir tmp;
  const CommandResult r =
      RunImuconv("bench --json --benchmark-args=--benchmark_min_time=0.01", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(Has(r.err, "imuconv bench:")) << r.err;  // a plugin that failed to load
  const json j = json::parse(r.out);
  std::map<std::string, json> ran;
  for (const auto& b : j.at("benchmarks")) ran[b.at("name").get<std::string>()] = b;
  std::vector<std::string> names{"BM_Preintegrate/manifold",
                                 "BM_Preintegrate/tangent",
                                 "BM_Preintegrate/vins_fusion",
                                 "BM_Preintegrate/basalt",
                                 "BM_Propagate/euler",
                                 "BM_Propagate/midpoint",
                                 "BM_Propagate/rk4",
                                 "BM_Propagate/openvins_discrete",
                                 "BM_Propagate/openvins_rk4",
                                 "BM_Propagate/openvins_analytical",
                                 "BM_Propagate/fast_lio2_as_configured",
                                 "BM_PreintegrateByPropagation/rk4",
                                 "BM_Conversion/left/gtsam_navstate",
                                 "BM_PluginOverhead/rk4/manual_time"};
  const std::pair<imuconv::kernels::Isa, const char*> instances[] = {
      {imuconv::kernels::Isa::kPortable, "portable"},
      {imuconv::kernels::Isa::kBaseline, "baseline"},
      {imuconv::kernels::Isa::kAvx2, "avx2"},
      {imuconv::kernels::Isa::kAvx512, "avx512"}};
  for (const char* scheme : {"manifold", "tangent"})
    for (const auto& [isa, name] : instances)
      if (imuconv::kernels::IsaAvailable(isa))
        names.push_back(std::string("BM_PreintegrateInstance/") + scheme + "/" + name);
  for (const auto& [isa, name] :
       instances)  // rk4's instances; kBaseline runs the portable code (bench/suite.cpp)
    if (isa != imuconv::kernels::Isa::kBaseline && imuconv::kernels::IsaAvailable(isa))
      names.push_back(std::string("BM_Rk4Instance/") + name);
  for (const char* name : {"BM_MonteCarlo/rk4", "BM_MonteCarlo/rk4_full_path"})
    names.push_back(name);  // montecarlo's trials
  for (const char* name :
       {"BM_WholeJob/euroc_full_json/manual_time", "BM_WholeJob/euroc_full_npz/manual_time"})
    names.push_back(name);  // imuconv run on examples/euroc_v1_01_full.json, in-process
  for (const std::string& name : names) {
    ASSERT_TRUE(ran.count(name)) << name << " did not run\n" << r.out;
    const json& b = ran[name];
    if (b.contains("error_occurred") && b["error_occurred"].get<bool>()) {
      ADD_FAILURE() << name << " failed: " << b.value("error_message", std::string());
      continue;
    }
    const double rate = b.at("items_per_second").get<double>();
    EXPECT_TRUE(std::isfinite(rate) && rate > 0.0) << b.dump();
  }
  EXPECT_TRUE(
      std::isfinite(ran["BM_PluginOverhead/rk4/manual_time"].at("overhead_pct").get<double>()));
  EXPECT_EQ(ran.size(), names.size()) << r.out;  // nothing unlisted either
}

}  // namespace
