// imuconv check: GTSAM's reference numbers (tests/data/reference) in disguises made here, the
// project's own measurements in every increment convention, the exit codes and hostile input.
//
// The verdict tolerance is check's own (1e-2 on the max of each scale-aware difference,
// apps/check/verdict.cpp); these tests assert what check must conclude and bound the
// differences it reports by what the inputs are:
//   - GTSAM's zero-order-hold numbers are euler's up to round-off: max d <= 1e-9 (measured:
//     about 1e-13; the conversions lose a few digits on entries that are small differences);
//   - a covariance doubled is off by exactly 1 on every diagonal entry on the correlation
//     scale (|2K - K| / K): max d in [0.99, 1.01];
//   - a density used as a variance is off by orders of magnitude: max d > 10.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "gtsam_measurement.h"
#include "imuconv/bridge.h"
#include "imuconv_test.h"
#include "json_rows.h"
#include "json_schema_check.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;
using nlohmann::json;

struct Checked {
  int exit_code = -1;
  json out;
  std::string err;
};

class Check : public ::testing::Test {
 protected:
  static TempDir& Tmp() {
    static TempDir tmp;
    return tmp;
  }
  /// Runs imuconv check --json on one file of `measurements`; every --json output is kept for
  /// the schema test.
  static Checked Run(const json& measurements, const std::string& case_id,
                     const std::string& name) {
    const std::string file =
        Tmp().write(name + ".json", json{{"measurements", measurements}}.dump());
    const CommandResult r =
        RunImuconv("check " + ShellQuote(file) + " --case " +
                       ShellQuote(DataPath("reference/cases/" + case_id + ".json")) + " --json",
                   Tmp());
    Checked c{r.exit_code, json(), r.err};
    if (r.exit_code == 0 || r.exit_code == 1) {
      c.out = json::parse(r.out);
      Outputs().push_back(c.out);
    }
    return c;
  }
  static std::vector<json>& Outputs() {
    static std::vector<json> outputs;
    return outputs;
  }
  /// Prints the best explanation of measurement 0 and its differences (the figures of
  /// docs/check.md).
  static void Print(const std::string& what, const json& out) {
    const json& b = out["measurements"][0]["best"];
    std::string blocks, cols;
    for (const auto& x : b["blocks"]) blocks += (blocks.empty() ? "" : ",") + x.get<std::string>();
    for (const auto& x : b["J_bias_columns"])
      cols += (cols.empty() ? "" : ",") + x.get<std::string>();
    std::printf(
        "  %-12s %s: %s %s [%s], J %s [%s] sign %d; max d delta %.2g J_bias %.2g cov %.2g\n",
        what.c_str(), out["measurements"][0]["verdict"].get<std::string>().c_str(),
        b["scheme"].get<std::string>().c_str(), b["convention"].get<std::string>().c_str(),
        blocks.c_str(), b["jacobian_convention"].get<std::string>().c_str(), cols.c_str(),
        b["J_bias_sign"].get<int>(), b["delta"]["max_d"].get<double>(),
        b["J_bias"]["max_d"].get<double>(), b["cov"]["max_d"].get<double>());
  }
  static std::string Findings(const json& m) {
    std::string s;
    for (const auto& f : m["findings"]) s += f.get<std::string>() + "\n";
    return s;
  }
  /// The best explanation's covariance is in GTSAM's own chart and block order.
  static void ExpectGtsamChartAndOrder(const json& best) {
    EXPECT_EQ(best["convention"], "gtsam_manifold");
    EXPECT_EQ(best["blocks"], json({"theta", "p", "v", "ba", "bg"}));
  }
};

// ---- GTSAM's numbers, as they are and in disguise ----

TEST_F(Check, GtsamNumbersAsDeclaredAreConsistentWithEuler) {
  for (const char* id : {"smooth-0", "aggressive-0", "jitter-0", "static-0", "white-0"}) {
    const Checked c = Run(json::array({GtsamMeasurement(id)}), id, std::string("plain-") + id);
    ASSERT_EQ(c.exit_code, 0) << id << c.err << c.out.dump(1);
    Print(id, c.out);
    const json& m = c.out["measurements"][0];
    EXPECT_EQ(m["verdict"], "consistent");
    EXPECT_EQ(m["best"]["scheme"], "euler") << id;
    ExpectGtsamChartAndOrder(m["best"]);
    EXPECT_EQ(m["best"]["J_bias_columns"], json({"ba", "bg"}));
    for (const char* part : {"delta", "J_bias", "cov"})
      EXPECT_LE(m["best"][part]["max_d"].get<double>(), 1e-9) << id << part;
  }
}

TEST_F(Check, GtsamNumbersStoredAsFloatAreConsistent) {
  // Every number of the increment, J_bias and covariance rounded to single precision (a dump
  // from float storage): relative changes of 6e-8 per entry, far inside check's 1e-2.
  json m = GtsamMeasurement("aggressive-1");
  const std::function<void(json&)> to_float = [&](json& j) {
    if (j.is_number_float()) j = static_cast<double>(static_cast<float>(j.get<double>()));
    if (j.is_structured())
      for (auto& x : j) to_float(x);
  };
  for (const char* key : {"delta", "J_bias", "cov"}) to_float(m[key]);
  const Checked c = Run(json::array({m}), "aggressive-1", "float");
  ASSERT_EQ(c.exit_code, 0) << c.err << c.out.dump(1);
  Print("float", c.out);
  const json& r = c.out["measurements"][0];
  EXPECT_EQ(r["best"]["scheme"], "euler");
  for (const char* part : {"delta", "J_bias", "cov"})
    EXPECT_LE(r["best"][part]["max_d"].get<double>(), 1e-5) << part;
}

TEST_F(Check, UndeclaredChartsAreFound) {
  json m = GtsamMeasurement("smooth-0");
  m["cov"]["convention"] = "unknown";
  m["cov"]["blocks"] = "unknown";
  m["J_bias"] = {{"convention", "unknown"},
                 {"cols", {{"blocks", "unknown"}}},
                 {"matrix", m["J_bias"]["matrix"]}};
  const Checked c = Run(json::array({m}), "smooth-0", "undeclared");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  Print("undeclared", c.out);
  const json& r = c.out["measurements"][0];
  EXPECT_EQ(r["declared"]["convention"], "unknown");
  ExpectGtsamChartAndOrder(r["best"]);
  EXPECT_EQ(r["best"]["J_bias_columns"], json({"ba", "bg"}));
  EXPECT_EQ(r["best"]["J_bias_sign"], 1);
  // The rows [theta, p, v] of preint_reference, gtsam_manifold_jacobian and forster are the
  // same perturbations of the rotation and the additive p, v: any of them is right. The one
  // found must reproduce GTSAM's J_bias to round-off.
  EXPECT_LE(r["best"]["J_bias"]["max_d"].get<double>(), 1e-9);
  EXPECT_LE(r["best"]["cov"]["max_d"].get<double>(), 1e-9);
}

TEST_F(Check, MislabelledConventionIsNamed) {
  json m = GtsamMeasurement("smooth-0");
  m["cov"]["convention"] = "gtsam_tangent";  // gtsam_tangent's blocks are in the same order
  m["J_bias"] = {{"convention", "gtsam_manifold_jacobian"}, {"matrix", m["J_bias"]["matrix"]}};
  const Checked c = Run(json::array({m}), "smooth-0", "mislabelled");
  ASSERT_EQ(c.exit_code, 1) << c.err;
  Print("mislabelled", c.out);
  const json& r = c.out["measurements"][0];
  EXPECT_EQ(r["verdict"], "inconsistent");
  EXPECT_EQ(r["best"]["convention"], "gtsam_manifold");
  EXPECT_LE(r["best"]["cov"]["max_d"].get<double>(), 1e-9);
  EXPECT_GT(r["under_declaration"]["cov"]["max_d"].get<double>(), 1e-2);
  EXPECT_TRUE(Has(Findings(r), "not the declared gtsam_tangent")) << Findings(r);
  EXPECT_TRUE(Has(Findings(r), "fix: declare cov.convention \"gtsam_manifold\"")) << Findings(r);
}

TEST_F(Check, PermutedBlocksAreFound) {
  // Random orderings (a fixed seed), each written as if it were GTSAM's own order.
  std::mt19937 rng(11);
  const std::vector<std::string> own = {"theta", "p", "v", "ba", "bg"};
  for (int trial = 0; trial < 3; ++trial) {
    std::array<int, 5> perm{0, 1, 2, 3, 4};
    do std::shuffle(perm.begin(), perm.end(), rng);
    while (perm == std::array<int, 5>{0, 1, 2, 3, 4});
    Eigen::MatrixXd cov;
    json m = GtsamMeasurement("smooth-0", nullptr, &cov);
    Eigen::MatrixXd permuted(15, 15);
    std::vector<std::string> order;
    for (int i = 0; i < 5; ++i) {
      order.push_back(own[perm[i]]);
      for (int j = 0; j < 5; ++j)
        permuted.block<3, 3>(3 * i, 3 * j) = cov.block<3, 3>(3 * perm[i], 3 * perm[j]);
    }
    m["cov"]["matrix"] = JsonRows(permuted);
    const Checked c = Run(json::array({m}), "smooth-0", "permuted" + std::to_string(trial));
    ASSERT_EQ(c.exit_code, 1) << c.err;
    Print("permuted", c.out);
    const json& r = c.out["measurements"][0];
    EXPECT_EQ(r["best"]["convention"], "gtsam_manifold");
    EXPECT_EQ(r["best"]["blocks"], json(order));
    EXPECT_LE(r["best"]["cov"]["max_d"].get<double>(), 1e-9);
    std::string listed;
    for (const auto& b : order) listed += (listed.empty() ? "" : ", ") + b;
    EXPECT_TRUE(Has(Findings(r), "the covariance is gtsam_manifold, but the blocks are [" + listed +
                                     "], not the declared [theta, p, v, ba, bg]"))
        << Findings(r);
  }
}

TEST_F(Check, SwappedJacobianColumnsAreFound) {
  Eigen::MatrixXd J;
  json m = GtsamMeasurement("aggressive-0", &J);
  Eigen::MatrixXd swapped(9, 6);
  swapped << J.rightCols(3), J.leftCols(3);
  m["J_bias"]["matrix"] = JsonRows(swapped);
  const Checked c = Run(json::array({m}), "aggressive-0", "swapped");
  ASSERT_EQ(c.exit_code, 1) << c.err;
  Print("swapped", c.out);
  const json& r = c.out["measurements"][0];
  EXPECT_EQ(r["best"]["J_bias_columns"], json({"bg", "ba"}));
  EXPECT_LE(r["best"]["J_bias"]["max_d"].get<double>(), 1e-9);
  EXPECT_TRUE(Has(Findings(r), "J_bias's columns are [bg, ba], not the declared [ba, bg]"))
      << Findings(r);
}

TEST_F(Check, FlippedJacobianSignIsFound) {
  Eigen::MatrixXd J;
  json m = GtsamMeasurement("smooth-1", &J);
  m["J_bias"]["matrix"] = JsonRows(-J);
  const Checked c = Run(json::array({m}), "smooth-1", "flipped");
  ASSERT_EQ(c.exit_code, 1) << c.err;
  Print("flipped", c.out);
  const json& r = c.out["measurements"][0];
  EXPECT_EQ(r["best"]["J_bias_sign"], -1);
  EXPECT_LE(r["best"]["J_bias"]["max_d"].get<double>(), 1e-9);
  EXPECT_TRUE(Has(Findings(r), "J_bias has the opposite sign")) << Findings(r);
  EXPECT_TRUE(Has(Findings(r), "negate J_bias")) << Findings(r);
}

TEST_F(Check, DoubledCovarianceIsExplainedByNothing) {
  Eigen::MatrixXd cov;
  json m = GtsamMeasurement("smooth-0", nullptr, &cov);
  m["cov"]["matrix"] = JsonRows(2.0 * cov);
  const Checked c = Run(json::array({m}), "smooth-0", "doubled");
  ASSERT_EQ(c.exit_code, 1) << c.err;
  Print("doubled", c.out);
  const json& r = c.out["measurements"][0];
  ExpectGtsamChartAndOrder(r["best"]);
  EXPECT_NEAR(r["best"]["cov"]["max_d"].get<double>(), 1.0, 0.01);
  EXPECT_TRUE(Has(Findings(r), "nothing registered explains")) << Findings(r);
  // The diagonal ratios name the factor, the same in every block.
  EXPECT_TRUE(Has(Findings(r), "theta 2, p 2, v 2, ba 2, bg 2")) << Findings(r);
}

TEST_F(Check, DensityUsedAsVarianceIsExplainedByNothing) {
  // A preintegration made with each density squared, as code that takes a variance where a
  // density is meant computes it; imuconv's euler is GTSAM's zero-order hold (to ~1e-13,
  // GtsamNumbersAsDeclaredAreConsistentWithEuler), written in GTSAM's charts.
  const json c = CaseJson("white-0");
  const std::vector<ImuSample> samples = CaseSamples(c);
  ImuNoise squared = CaseNoise(c);
  for (double* d : {&squared.gyro_noise_density, &squared.accel_noise_density,
                    &squared.gyro_random_walk, &squared.accel_random_walk})
    *d = *d * *d;
  SampleWindow w;
  ASSERT_TRUE(
      MakeWindow(samples.data(), samples.size(), samples.front().t, samples.back().t, w).ok());
  const Preintegrated p = PreintegrateByPropagation(
      Plugins(), "euler", w, JsonVec3(c["state_s"]["bg"]), JsonVec3(c["state_s"]["ba"]), squared);
  json m = GtsamMeasurement("white-0");
  m["cov"]["matrix"] = JsonRows(Express(Plugins(), p, "gtsam_manifold").cov);
  const Checked r = Run(json::array({m}), "white-0", "variance");
  ASSERT_EQ(r.exit_code, 1) << r.err;
  Print("variance", r.out);
  const json& o = r.out["measurements"][0];
  // The nearest covariance is still GTSAM's chart and order (by its correlation structure).
  ExpectGtsamChartAndOrder(o["best"]);
  // Every variance is far smaller than the case's noise gives (densities below 1 squared), so
  // on the correlation scale each diagonal entry is off by nearly all of itself: d -> 1.
  EXPECT_GT(o["best"]["cov"]["max_d"].get<double>(), 0.99);
  EXPECT_LE(o["best"]["J_bias"]["max_d"].get<double>(), 1e-9);  // the noise does not touch J_bias
  EXPECT_TRUE(Has(Findings(o), "no convention or block order explains the covariance"))
      << Findings(o);
  // The ratios name the cause: the rotation block is driven by the gyro's white noise alone
  // (its random walk adds 0.2 % over these 10 s), so its variances shrank by the gyro density
  // squared; the two digits printed are those of gyro_noise_density^2.
  const double g = CaseNoise(c).gyro_noise_density;
  char expect[64];
  std::snprintf(expect, sizeof expect, "theta %.2g,", g * g);
  EXPECT_TRUE(Has(Findings(o), expect)) << expect << "\n" << Findings(o);
}

// ---- the project's own measurements, every increment convention ----

// `intervals` 1 s intervals of a case from its start, preintegrated by `method` (a propagator or
// a native preintegrator), written in `convention` fully declared, or with every chart "unknown".
json OwnMeasurements(const std::string& id, const std::string& method, bool native,
                     const std::string& convention, bool declared, int intervals) {
  const json c = CaseJson(id);
  const std::vector<ImuSample> samples = CaseSamples(c);
  const Registry& reg = Plugins();
  json ms = json::array();
  const double t0 = samples.front().t;
  for (int k = 0; k < intervals; ++k) {
    SampleWindow w;
    const double ts = t0 + k, te = t0 + k + 1;
    EXPECT_TRUE(MakeWindow(samples.data(), samples.size(), ts, te, w).ok());
    const Vec3 bg = JsonVec3(c["state_s"]["bg"]), ba = JsonVec3(c["state_s"]["ba"]);
    const Preintegrated p = native
                                ? PreintegrateNative(reg, method, w, bg, ba, CaseNoise(c))
                                : PreintegrateByPropagation(reg, method, w, bg, ba, CaseNoise(c));
    const Preintegrated in = Express(reg, p, convention);
    const auto& cov_blocks = reg.info(PluginKind::IncrementConvention, convention).blocks;
    std::vector<std::string> rows, cols;
    for (const auto& b : reg.info(PluginKind::IncrementConvention, in.jacobian_convention).blocks)
      (b == "bg" || b == "ba" ? cols : rows).push_back(b);
    json m = {{"t_start", ts},
              {"t_end", te},
              {"dt", p.dt},
              {"bias_estimate", {{"bg", {bg[0], bg[1], bg[2]}}, {"ba", {ba[0], ba[1], ba[2]}}}},
              {"delta",
               {{"R", JsonRows(p.delta.dR)},
                {"dp", {p.delta.dp[0], p.delta.dp[1], p.delta.dp[2]}},
                {"dv", {p.delta.dv[0], p.delta.dv[1], p.delta.dv[2]}}}}};
    if (declared) {
      m["cov"] = {{"convention", convention}, {"blocks", cov_blocks}, {"matrix", JsonRows(in.cov)}};
      m["J_bias"] = {{"rows", {{"convention", in.jacobian_convention}, {"blocks", rows}}},
                     {"cols", {{"convention", in.jacobian_convention}, {"blocks", cols}}},
                     {"matrix", JsonRows(in.J_bias)}};
    } else {
      m["cov"] = {{"convention", "unknown"}, {"matrix", JsonRows(in.cov)}};
      m["J_bias"] = {{"convention", "unknown"}, {"matrix", JsonRows(in.J_bias)}};
    }
    ms.push_back(m);
  }
  return ms;
}

TEST_F(Check, OwnMeasurementsInEveryConventionAreConsistent) {
  // Propagated by each propagator check compares with, and every native preintegrator, each
  // the same computation as one of check's references (manifold is euler's computation by
  // another route; the others are references of their own), so every difference is
  // round-off: 1e-9 (measured: at most 2.1e-13). Every method and every increment convention
  // is covered, in pairs that rotate through both lists: run k holds method k's two 1 s
  // intervals in conventions k and k + 1 (mod their counts), each declared and undeclared, for
  // max(methods, conventions) runs. A convention's reading does not depend on the scheme that
  // produced the numbers (the registry converts any measurement the same way, and the scheme
  // and convention searches are tested against each other by the other Check cases), so the
  // rotation covers what the full product of methods and conventions did, at a cost linear in
  // each list instead of their product: every system added both lists grow, and under ASan
  // one run of this file per method in all seven conventions took 283 s.
  std::vector<std::tuple<std::string, bool, std::string>> methods = {
      {"euler", false, "euler"}, {"midpoint", false, "midpoint"}, {"rk4", false, "rk4"}};
  for (const auto& id : Plugins().ids(PluginKind::Preintegrator))
    methods.emplace_back(id, true, id == "manifold" ? "euler" : id);
  const auto conventions = Plugins().ids(PluginKind::IncrementConvention);
  ASSERT_GE(conventions.size(), 2u);
  std::set<std::string> methods_seen, conventions_seen;
  const std::size_t runs = std::max(methods.size(), conventions.size());
  for (std::size_t k = 0; k < runs; ++k) {
    const auto& [method, native, scheme] = methods[k % methods.size()];
    json ms = json::array();
    std::vector<std::string> what;
    for (std::size_t c : {k % conventions.size(), (k + 1) % conventions.size()}) {
      const std::string& convention = conventions[c];
      conventions_seen.insert(convention);
      for (bool declared : {true, false})
        for (const json& m : OwnMeasurements("smooth-2", method, native, convention, declared, 2)) {
          ms.push_back(m);
          what.push_back(method + " in " + convention + (declared ? " declared" : " undeclared"));
        }
    }
    methods_seen.insert(method);
    const Checked c = Run(ms, "smooth-2", "own-" + method + "-" + std::to_string(k));
    ASSERT_EQ(c.exit_code, 0) << method << "\n" << c.err << c.out.dump(1);
    ASSERT_EQ(c.out["measurements"].size(), ms.size()) << method;
    double worst = 0.0;
    for (std::size_t i = 0; i < ms.size(); ++i) {
      const json& m = c.out["measurements"][i];
      EXPECT_EQ(m["best"]["scheme"], scheme) << what[i];
      if (ms[i]["cov"]["convention"] != "unknown") {
        EXPECT_EQ(m["best"]["convention"], ms[i]["cov"]["convention"]) << what[i];
      }
      double worst_i = 0.0;
      for (const char* part : {"J_bias", "cov"})
        worst_i = std::max(worst_i, m["best"][part]["max_d"].get<double>());
      EXPECT_LE(worst_i, 1e-9) << what[i];
      // orb_slam3 computes in float: its rotation is orthogonal only to float precision, and
      // the measurements form reads R as Exp(Log(R)) (forms/input_checks.cpp), which moves it
      // by that, about 1e-7 per entry and up to 2e-6 relative to an entry above the metric's
      // floor (measured). Its increment is judged at the issue's float bound, 1e-4; every other
      // method's at 1e-9, and every method's J_bias and cov above.
      const double delta_d = m["best"]["delta"]["max_d"].get<double>();
      EXPECT_LE(delta_d, method == "orb_slam3" ? 1e-4 : 1e-9) << what[i];
      worst_i = std::max(worst_i, delta_d);
      worst = std::max(worst, worst_i);
    }
    std::printf("  %-28s worst max d %.2g over %zu measurements (%s)\n", method.c_str(), worst,
                ms.size(), what.front().c_str());
  }
  EXPECT_EQ(methods_seen.size(), methods.size());
  EXPECT_EQ(conventions_seen.size(), conventions.size());
}

// ---- exit codes and hostile input ----

TEST_F(Check, UnusableInputExitsWithTwoNamingFileAndPointer) {
  TempDir& tmp = Tmp();
  const std::string case_path = ShellQuote(DataPath("reference/cases/smooth-0.json"));
  CommandResult r =
      RunImuconv("check " + ShellQuote(tmp.file("missing.json")) + " --case " + case_path, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "missing.json")) << r.err;

  // check on the measurements `ms`, written to the file `name`, against smooth-0.
  const auto check_written = [&](const std::string& name, const std::vector<json>& ms) {
    return RunImuconv("check " + ShellQuote(tmp.write(name, json{{"measurements", ms}}.dump())) +
                          " --case " + case_path,
                      tmp);
  };

  json m = GtsamMeasurement("smooth-0");
  r = RunImuconv("check " + ShellQuote(tmp.write("ok.json", json{{"measurements", {m}}}.dump())) +
                     " --case " + ShellQuote(tmp.file("no-case.json")),
                 tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "no-case.json")) << r.err;

  // A case whose samples have a gap (rows 500..599 removed: 0.5 s at 200 Hz).
  json gap_case = CaseJson("smooth-0");
  gap_case["imu"].erase(gap_case["imu"].begin() + 500, gap_case["imu"].begin() + 600);
  r = RunImuconv("check " + ShellQuote(tmp.file("ok.json")) + " --case " +
                     ShellQuote(tmp.write("gap.json", gap_case.dump())),
                 tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "gap.json") && Has(r.err, "/imu/500/0") && Has(r.err, "gap")) << r.err;

  json bad = m;
  bad["cov"]["matrix"].erase(bad["cov"]["matrix"].begin());  // 14 rows
  r = check_written("bad.json", {bad});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "bad.json") && Has(r.err, "/measurements/0/cov/matrix")) << r.err;

  json typo = m;
  typo["cov"]["convention"] = "gtsam_manifolds";
  r = check_written("typo.json", {typo});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "/measurements/0/cov/convention")) << r.err;

  json blocks = m;
  blocks["cov"]["blocks"] = {"theta", "p", "v", "ba", "ba"};
  r = check_written("blocks.json", {blocks});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "/measurements/0/cov/blocks") && Has(r.err, "not an ordering")) << r.err;

  // A measurement of another time range than the case's samples.
  json late = m;
  late["t_start"] = m["t_start"].get<double>() + 100.0;
  late["t_end"] = m["t_end"].get<double>() + 100.0;
  r = check_written("late.json", {m, late});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "late.json") && Has(r.err, "/measurements/1") &&
              Has(r.err, "not inside the case's samples"))
      << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

// A bias estimate at which every scheme's numbers overflow (1e160 rad/s) is bad input, not a
// verdict: before, check compared inf and NaN, every explanation tied and it printed
// "inconsistent" (exit 1). A large but finite one (1e3 rad/s) is still judged: the file's
// increment was not made at it.
TEST_F(Check, ABiasEstimateWhereEverySchemeOverflowsIsRefused) {
  json m = GtsamMeasurement("smooth-0");
  m["bias_estimate"]["bg"] = {1e160, 0.0, 0.0};
  const Checked overflow = Run(json::array({m}), "smooth-0", "overflowing_bias");
  EXPECT_EQ(overflow.exit_code, 2) << overflow.err;
  EXPECT_TRUE(Has(overflow.err, "overflowing_bias.json") && Has(overflow.err, "/measurements/0") &&
              Has(overflow.err, "not finite at the measurement's bias estimate"))
      << overflow.err;
  m["bias_estimate"]["bg"] = {1e3, 0.0, 0.0};
  const Checked large = Run(json::array({m}), "smooth-0", "large_bias");
  EXPECT_EQ(large.exit_code, 1) << large.err;
}

TEST_F(Check, TableWithoutJson) {
  TempDir& tmp = Tmp();
  json m = GtsamMeasurement("smooth-0");
  Eigen::MatrixXd J;
  json flipped = GtsamMeasurement("smooth-0", &J);
  flipped["J_bias"]["matrix"] = JsonRows(-J);
  const std::string f = tmp.write("table.json", json{{"measurements", {m, flipped}}}.dump());
  const CommandResult r = RunImuconv(
      "check " + ShellQuote(f) + " --case " + ShellQuote(DataPath("reference/cases/smooth-0.json")),
      tmp);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(Has(r.out, "consistent") && Has(r.out, "INCONSISTENT") &&
              Has(r.out, "verdict: inconsistent"))
      << r.out;
}

// Outputs of every kind (consistent; a wrong declaration with its fix; nothing explains;
// undeclared charts) against schemas/check_output.schema.json, with Debian's
// python3-jsonschema (Draft 2020-12, as tests/pipeline/validate_schemas.py).
TEST_F(Check, OutputsFollowTheSchema) {
  TempDir& tmp = Tmp();
  Eigen::MatrixXd J, cov;
  const json plain = GtsamMeasurement("smooth-0", &J, &cov);
  json flipped = plain, doubled = plain, unknown = plain;
  flipped["J_bias"]["matrix"] = JsonRows(-J);
  doubled["cov"]["matrix"] = JsonRows(2.0 * cov);
  unknown["cov"] = {{"convention", "unknown"}, {"matrix", plain["cov"]["matrix"]}};
  unknown["J_bias"] = {{"convention", "unknown"}, {"matrix", plain["J_bias"]["matrix"]}};
  Outputs().clear();
  Run(json::array({plain, flipped, doubled, unknown}), "smooth-0", "schema");
  Run(json::array({plain}), "smooth-0", "schema-plain");
  ASSERT_EQ(Outputs().size(), 2u);
  ExpectFollowsSchema(tmp, "schemas/check_output.schema.json", json(Outputs()), "outputs");
}

}  // namespace
