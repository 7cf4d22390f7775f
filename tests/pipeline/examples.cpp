// Every example pipeline runs, its output labels every matrix with its chart, and the
// numbers check out against independent expectations (tolerances stated per test).
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/so3.h"
#include "imuconv_test.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using imuconv::test::JsonMatrix;
using imuconv::test::SourcePath;
using nlohmann::json;

json RunExample(const std::string& name, std::string* summary = nullptr) {
  const Pipeline p = Pipeline::Load(SourcePath("examples/" + name));
  std::ostringstream s;
  RunOptions o;
  o.summary = &s;
  json out = pipeline::Run(p, imuconv::test::Plugins(), o);
  if (summary) *summary = s.str();
  // The written form parses back to the same document.
  EXPECT_EQ(json::parse(PrettyJson(out)), out);
  return out;
}

Vec3 V3(const json& j) { return Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>()); }
Mat3 Rot(const json& state) {
  const auto& q = state["q_wxyz"];
  return so3::FromQuaternionWxyz(q[0], q[1], q[2], q[3]);
}

TEST(Examples, EveryExampleRunsAndLabelsItsMatrices) {
  for (const char* name : {"euroc_v1_01_keyframes.json", "inline_basics.json", "generic_csv.json",
                           "gtsam_import.json"}) {
    SCOPED_TRACE(name);
    const json out = RunExample(name);
    EXPECT_GT(imuconv::test::CheckMatricesLabelled(out), 0u);
    EXPECT_FALSE(out["tasks"].empty());
  }
}

TEST(Examples, EurocKeyframes) {
  std::string summary;
  const json out = RunExample("euroc_v1_01_keyframes.json", &summary);
  EXPECT_EQ(out["time_origin_ns"].get<std::int64_t>(), 1403715293262142976LL);
  for (const char* pre : {"kf_rk4", "kf_manifold"}) {
    const json& ms = TaskOutput(out, pre)["measurements"];
    ASSERT_EQ(ms.size(), 200u);
    for (std::size_t k = 0; k < ms.size(); ++k) {
      // 10 Hz keyframes on the absolute time axis, exact to the nanosecond.
      ASSERT_EQ(ms[k]["t_start_abs_ns"].get<std::int64_t>(),
                1403715293262142976LL + static_cast<std::int64_t>(k) * 100000000LL);
      ASSERT_NEAR(ms[k]["dt"].get<double>(), 0.1, 1e-12);
      ASSERT_TRUE(ms[k]["expressed"].contains("gtsam_manifold"));
    }
  }
  // Each interval starts from the ground truth; over 0.1 s the prediction with ground-truth
  // biases must stay close to the ground truth at its end. Observed: RMS 0.29 mm / 0.013 deg
  // (rk4) and 0.42 mm / 0.024 deg (manifold, zero-order hold); the bounds leave ~3x room
  // (the ground truth itself is a batch estimate, not exact).
  for (const char* pred : {"pred_rk4", "pred_manifold"}) {
    const json& s = TaskOutput(out, pred)["ground_truth_summary"];
    EXPECT_EQ(s["intervals"], 200);
    EXPECT_LT(s["rms_position_error_m"].get<double>(), 1.5e-3) << pred;
    EXPECT_LT(s["rms_rotation_error_deg"].get<double>(), 0.08) << pred;
    EXPECT_LT(s["max_position_error_m"].get<double>(), 4e-3) << pred;
    EXPECT_LT(s["max_rotation_error_deg"].get<double>(), 0.3) << pred;
  }
  EXPECT_NE(summary.find(
                "     k   t_start[s]   dt[s]    |dp|[m]   angle[deg]   pos.err[m]   rot.err[deg]"),
            std::string::npos);
  EXPECT_NE(summary.find(" total (200)        20.0000"), std::string::npos) << summary;
  EXPECT_NE(summary.find("rms over 200 interval(s)"), std::string::npos) << summary;
}

TEST(Examples, InlineBasicsPropagationByPreintegrationMatchesPropagation) {
  // The same RK4 over [0, 0.2] s, once directly and once as two chained preintegrated
  // 0.1 s intervals: the paper's equivalence, here to round-off (observed 1e-15 on the
  // state, 6e-13 relative on the covariance; bounds 1e-12 and 1e-10).
  const json out = RunExample("inline_basics.json");
  const json& direct = TaskOutput(out, "direct");
  const json& steps = TaskOutput(out, "by_preint")["steps"];
  ASSERT_EQ(steps.size(), 2u);
  const json& last = steps[1];
  EXPECT_LT((V3(direct["x_e"]["p"]) - V3(last["x_e"]["p"])).norm(), 1e-12);
  EXPECT_LT((V3(direct["x_e"]["v"]) - V3(last["x_e"]["v"])).norm(), 1e-12);
  EXPECT_LT(so3::Log(Rot(direct["x_e"]).transpose() * Rot(last["x_e"])).norm(), 1e-12);
  EXPECT_EQ(direct["cov"]["convention"], "left");
  EXPECT_LT(
      imuconv::test::RelErr(JsonMatrix(last["cov"]["matrix"]), JsonMatrix(direct["cov"]["matrix"])),
      1e-10);
  // The covariance conversion task equals the registry's own conversion (same code path: 1e-12).
  const json& cv = TaskOutput(out, "cov_navstate");
  ImuState xe;
  xe.p = V3(direct["x_e"]["p"]);
  xe.v = V3(direct["x_e"]["v"]);
  xe.R = Rot(direct["x_e"]);
  xe.bg = V3(direct["x_e"]["bg"]);
  xe.ba = V3(direct["x_e"]["ba"]);
  const Mat15 expect = imuconv::test::Plugins().convert_covariance(
      "left", "gtsam_navstate", xe, JsonMatrix(direct["cov"]["matrix"]));
  EXPECT_LT(imuconv::test::RelErr(JsonMatrix(cv["result"]["matrix"]), expect), 1e-12);
  EXPECT_EQ(cv["result"]["blocks"], json({"theta", "p", "v", "ba", "bg"}));
  // First-order bias correction vs re-integration: a change of 2e-3 rad/s and 5e-2 m/s^2 over
  // 0.1 s leaves second-order differences (observed <= 1e-6); bound 1e-5 in every chart.
  for (const auto& u : TaskOutput(out, "rebias")["updates"])
    for (const auto& [chart, fo] : u["first_order"].items()) {
      EXPECT_LT(fo["vs_reintegrated"]["rotation_deg"].get<double>(), 1e-5) << chart;
      EXPECT_LT(fo["vs_reintegrated"]["dp_m"].get<double>(), 1e-5) << chart;
      EXPECT_LT(fo["vs_reintegrated"]["dv_mps"].get<double>(), 1e-5) << chart;
    }
}

TEST(Examples, GtsamImportReproducesGtsamsPrediction) {
  // The measurement file holds GTSAM's own ManifoldPreintegration numbers for reference case
  // smooth-0; predicting from the case's start state must give GTSAM's predict (R, p, v)
  // up to round-off of ~1e3 m positions (bound 1e-9 relative).
  const json ref =
      imuconv::test::ReadJson(imuconv::test::DataPath("reference/gtsam/smooth-0.gtsam.json"));
  const json& g = ref["zoh"]["manifold"]["predict"];
  const json out = RunExample("gtsam_import.json");
  const json& x = TaskOutput(out, "predict")["steps"][0]["x_e"];
  const Vec3 gp = V3(g["p"]), gv = V3(g["v"]);
  EXPECT_LT((V3(x["p"]) - gp).norm() / gp.norm(), 1e-9);
  EXPECT_LT((V3(x["v"]) - gv).norm() / gv.norm(), 1e-9);
  EXPECT_LT(so3::Log(Mat3(JsonMatrix(g["R"])).transpose() * Rot(x)).norm(), 1e-9);
  // GTSAM's residual at GTSAM's prediction is zero (bound 1e-8 on every entry).
  const json& r = TaskOutput(out, "residual_at_gtsam_prediction")["residuals"][0]["r"]["vector"];
  for (const auto& v : r) EXPECT_LT(std::abs(v.get<double>()), 1e-8);
  // The covariance conversion names its charts.
  const json& cl = TaskOutput(out, "cov_left");
  EXPECT_EQ(cl["from"], "gtsam_navstate");
  EXPECT_EQ(cl["result"]["convention"], "left");
}

TEST(Examples, GenericCsvAgreesWithTheSameDataInEurocFormat) {
  // generic_csv.json reads seconds with 9 decimals from a ';' file; the same preintegration
  // on the nanosecond EuRoC file must agree to round-off (bound 1e-12 on dp, dv, rotation).
  const json out = RunExample("generic_csv.json");
  json doc = imuconv::test::ReadJson(SourcePath("examples/generic_csv.json"));
  doc["imu"] = {{"format", "euroc"}, {"path", "data/V1_01_easy_imu0_slice.csv"}};
  doc["tasks"] = json::array({doc["tasks"][0]});
  const json ref =
      pipeline::Run(Pipeline::FromJson(doc, "euroc-variant.json", SourcePath("examples")),
                    imuconv::test::Plugins(), {});
  const json& a = TaskOutput(out, "kf_tangent")["measurements"];
  const json& b = TaskOutput(ref, "kf_tangent")["measurements"];
  ASSERT_EQ(a.size(), 4u);
  ASSERT_EQ(b.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(a[k]["n_knots"], b[k]["n_knots"]);
    EXPECT_EQ(a[k]["t_start_abs_ns"], b[k]["t_start_abs_ns"]);
    EXPECT_LT((V3(a[k]["delta"]["dp"]) - V3(b[k]["delta"]["dp"])).norm(), 1e-12);
    EXPECT_LT((V3(a[k]["delta"]["dv"]) - V3(b[k]["delta"]["dv"])).norm(), 1e-12);
    EXPECT_LT(so3::Log(Mat3(JsonMatrix(a[k]["delta"]["R"])).transpose() *
                       Mat3(JsonMatrix(b[k]["delta"]["R"])))
                  .norm(),
              1e-12);
  }
}

}  // namespace

namespace {

TEST(Examples, MeasurementsRoundTripThroughFiles) {
  // A preintegrate task's output measurements, written as a measurements file as they are
  // (preint_reference) and re-expressed in gtsam_manifold (the "expressed" block moved up),
  // give the same propagation by preintegration as the task itself: Express/FromConvention
  // and the JSON text round trip lose only round-off (bounds: 1e-12 on the state, 1e-9
  // relative on the covariance).
  const json out = RunExample("inline_basics.json");
  const json& ms = TaskOutput(out, "kf")["measurements"];
  json as_is = {{"measurements", ms}};
  json manifold = {{"measurements", json::array()}};
  for (const auto& m : ms) {
    json e = m;
    e["J_bias"] = m["expressed"]["gtsam_manifold"]["J_bias"];
    e["cov"] = m["expressed"]["gtsam_manifold"]["cov"];
    e.erase("expressed");
    manifold["measurements"].push_back(e);
  }
  imuconv::test::TempDir tmp;
  tmp.write("as_is.json", PrettyJson(as_is));
  tmp.write("manifold.json", PrettyJson(manifold));
  json doc = imuconv::test::ReadJson(SourcePath("examples/inline_basics.json"));
  json pbp = TaskOutput(doc, "by_preint");
  json tasks = json::array({doc["tasks"][1], pbp});
  for (const char* f : {"as_is.json", "manifold.json"}) {
    json t = pbp;
    t["name"] = std::string("from_") + f;
    t["name"] = t["name"].get<std::string>().substr(0, t["name"].get<std::string>().find('.'));
    t["measurements"] = {{"file", f}};
    tasks.push_back(t);
  }
  doc["tasks"] = tasks;
  const json res = pipeline::Run(Pipeline::FromJson(doc, "roundtrip.json", tmp.path()),
                                 imuconv::test::Plugins(), {});
  const json& ref = TaskOutput(res, "by_preint")["steps"];
  for (const char* name : {"from_as_is", "from_manifold"}) {
    SCOPED_TRACE(name);
    const json& st = TaskOutput(res, name)["steps"];
    ASSERT_EQ(st.size(), ref.size());
    for (std::size_t k = 0; k < st.size(); ++k) {
      EXPECT_EQ(st[k]["t_start"], ref[k]["t_start"]);
      EXPECT_LT((V3(st[k]["x_e"]["p"]) - V3(ref[k]["x_e"]["p"])).norm(), 1e-12);
      EXPECT_LT((V3(st[k]["x_e"]["v"]) - V3(ref[k]["x_e"]["v"])).norm(), 1e-12);
      EXPECT_LT(so3::Log(Rot(st[k]["x_e"]).transpose() * Rot(ref[k]["x_e"])).norm(), 1e-12);
      EXPECT_LT(imuconv::test::RelErr(JsonMatrix(st[k]["cov"]["matrix"]),
                                      JsonMatrix(ref[k]["cov"]["matrix"])),
                1e-9);
      EXPECT_LT(imuconv::test::RelErr(JsonMatrix(st[k]["Phi"]["matrix"]),
                                      JsonMatrix(ref[k]["Phi"]["matrix"])),
                1e-9);
    }
  }
}

}  // namespace

namespace {

TEST(Examples, OmitLeavesOutTheNamedMatrices) {
  // The whole-matrix outputs can be left out for small, fast outputs; everything else stays.
  json doc = imuconv::test::ReadJson(SourcePath("examples/euroc_v1_01_keyframes.json"));
  const json full = pipeline::Run(Pipeline::FromJson(doc, "full.json", SourcePath("examples")),
                                  imuconv::test::Plugins(), {});
  doc["omit"] = {"reference", "Phi"};
  const json light = pipeline::Run(Pipeline::FromJson(doc, "light.json", SourcePath("examples")),
                                   imuconv::test::Plugins(), {});
  doc["omit"] = {"Phi", "cov", "J_bias", "R"};
  const json bare = pipeline::Run(Pipeline::FromJson(doc, "bare.json", SourcePath("examples")),
                                  imuconv::test::Plugins(), {});
  const json& fm = TaskOutput(full, "kf_rk4")["measurements"][7];
  const json& lm = TaskOutput(light, "kf_rk4")["measurements"][7];
  const json& bm = TaskOutput(bare, "kf_rk4")["measurements"][7];
  // "reference": the preint_reference copies go, the expressed ones stay (the same numbers).
  EXPECT_TRUE(fm.contains("J_bias") && fm.contains("cov"));
  EXPECT_FALSE(lm.contains("J_bias") || lm.contains("cov"));
  EXPECT_EQ(lm["expressed"], fm["expressed"]);
  EXPECT_EQ(lm["delta"], fm["delta"]);
  // Phi, cov, J_bias, R: no matrices at all; states, increments and errors as before.
  EXPECT_FALSE(bm.contains("J_bias") || bm.contains("cov") || bm.contains("expressed") ||
               bm["delta"].contains("R"));
  EXPECT_EQ(bm["delta"]["q_wxyz"], fm["delta"]["q_wxyz"]);
  EXPECT_EQ(imuconv::test::CheckMatricesLabelled(bare), 0u);
  const json& fs = TaskOutput(full, "pred_rk4")["steps"][7];
  const json& ls = TaskOutput(light, "pred_rk4")["steps"][7];
  const json& bs = TaskOutput(bare, "pred_rk4")["steps"][7];
  EXPECT_FALSE(ls.contains("Phi"));
  EXPECT_EQ(ls["cov"], fs["cov"]);
  EXPECT_FALSE(bs.contains("Phi") || bs.contains("cov"));
  EXPECT_EQ(bs["x_e"], fs["x_e"]);
  EXPECT_EQ(bs["ground_truth"], fs["ground_truth"]);
  EXPECT_EQ(TaskOutput(bare, "pred_rk4")["ground_truth_summary"],
            TaskOutput(full, "pred_rk4")["ground_truth_summary"]);
  EXPECT_LT(bare.dump().size() * 5, full.dump().size());
  // Names are checked.
  doc["omit"] = {"Phi", "phi", "Phi"};
  try {
    Pipeline::FromJson(doc, "bad.json", SourcePath("examples"));
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    ASSERT_EQ(e.issues().size(), 2u) << e.what();
    EXPECT_EQ(e.issues()[0].pointer, "/omit/1");
    EXPECT_NE(e.issues()[0].message.find("'Phi'"), std::string::npos) << e.issues()[0].message;
    EXPECT_EQ(e.issues()[1].pointer, "/omit/2");
    EXPECT_EQ(e.issues()[1].message, "'Phi' is listed twice");
  }
}

}  // namespace
