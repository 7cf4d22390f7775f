// The output records which plugin file (and version) each plugin a task used came from, so
// that a plugin overriding a built-in id is visible; overriding is refused unless the user
// or the pipeline opts in.
#include <gtest/gtest.h>

#include "../../apps/pipeline/src/tasks/plugins_used.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"
#include "inline_pipeline.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using nlohmann::json;

const char* kProvenanceFile = "mem/provenance.json";

json Doc() {
  json prop = test::Rk4PropagationOverTenthSecond("prop", test::UnitSpeedStartState());
  prop["state_convention"] = "gtsam_navstate";
  return test::TenthSecondAt100HzRunning({prop,
                                          {{"type", "preintegrate"},
                                           {"name", "pre"},
                                           {"method", {{"preintegrator", "tangent"}}},
                                           {"conventions", {"gtsam_manifold"}},
                                           {"keyframes", {0.0, 0.1}}}});
}

/// "kind/id" -> the entry of the output's "plugins".
std::map<std::string, json> ByKey(const json& plugins) {
  std::map<std::string, json> m;
  for (const auto& p : plugins)
    m[p["kind"].get<std::string>() + "/" + p["id"].get<std::string>()] = p;
  return m;
}

TEST(Provenance, EveryPluginUsedIsListedWithItsFileAndVersion) {
  const Pipeline p = Pipeline::FromJson(Doc(), kProvenanceFile, IMUCONV_SOURCE_DIR);
  const json out = pipeline::Run(p, imuconv::test::Plugins(), RunOptions{});
  const auto used = ByKey(out["plugins"]);
  // Named by the tasks, implied by them (rk4's native chart, tangent's covariance and
  // bias-Jacobian charts, gtsam_manifold's bias-Jacobian chart) and the reference charts.
  for (const char* key :
       {"propagator/rk4", "preintegrator/tangent", "state_convention/gtsam_navstate",
        "state_convention/left", "preint_convention/gtsam_manifold",
        "preint_convention/gtsam_manifold_jacobian", "preint_convention/gtsam_tangent",
        "preint_convention/preint_reference"}) {
    SCOPED_TRACE(key);
    ASSERT_EQ(used.count(key), 1u) << out["plugins"].dump(1);
    const json& e = used.at(key);
    const PluginInfo& info = imuconv::test::Plugins().info(
        e["kind"] == "propagator"         ? PluginKind::Propagator
        : e["kind"] == "preintegrator"    ? PluginKind::Preintegrator
        : e["kind"] == "state_convention" ? PluginKind::StateConvention
                                          : PluginKind::IncrementConvention,
        e["id"].get<std::string>());
    EXPECT_EQ(e["file"], info.file);
    EXPECT_EQ(e["version"], info.version);
    EXPECT_FALSE(e["version"].get<std::string>().empty());
  }
  EXPECT_NE(used.at("propagator/rk4")["file"].get<std::string>().find(
                "imuconv_plugin_integrators_rk4.so"),
            std::string::npos);
  EXPECT_EQ(used.at("preint_convention/preint_reference")["file"], "built-in");
  // Plugins no task uses are not listed.
  EXPECT_EQ(used.count("propagator/euler"), 0u);
  EXPECT_EQ(used.count("state_convention/forster"), 0u);
}

TEST(Provenance, AnOverridingPluginIsRefusedUnlessAllowedAndThenVisible) {
  // tests/fixtures/override holds a propagator claiming the built-in id rk4 (it refuses to
  // integrate). Named by the pipeline's plugin_dirs, it is searched first.
  const std::string dir = std::string(IMUCONV_BINARY_DIR) + "/tests/fixtures/override";
  json doc = Doc();
  doc["plugin_dirs"] = {dir};
  const Pipeline refused = Pipeline::FromJson(doc, kProvenanceFile, IMUCONV_SOURCE_DIR);
  const std::string m = imuconv::test::MessageOf([&] { pipeline::Run(refused, RunOptions{}); });
  EXPECT_NE(m.find("imuconv_plugin_claims_rk4.so"), std::string::npos) << m;
  EXPECT_NE(m.find("imuconv_plugin_integrators_rk4.so"), std::string::npos) << m;
  // Allowed by the pipeline's key (or RunOptions::allow_plugin_override): the fixture is the
  // rk4 that runs, and the provenance names its file.
  for (const bool by_key : {true, false}) {
    SCOPED_TRACE(by_key ? "pipeline key" : "run option");
    json allowed = doc;
    RunOptions ro;
    if (by_key)
      allowed["allow_plugin_override"] = true;
    else
      ro.allow_plugin_override = true;
    const Pipeline p = Pipeline::FromJson(allowed, kProvenanceFile, IMUCONV_SOURCE_DIR);
    const std::string failure = imuconv::test::MessageOf([&] { pipeline::Run(p, ro); });
    EXPECT_NE(failure.find("fixture claims_rk4: not an integrator"), std::string::npos) << failure;
    Registry reg;
    LoadOptions lo;
    lo.allow_override = true;
    // The fixture's rk4 overrides the built-in one (said in one issue); nothing else may fail.
    for (const LoadIssue& i : reg.load_search_path({dir}, lo))
      EXPECT_TRUE(i.overridden) << i.file << ": " << i.message;
    const auto used = PluginsUsed(p.spec(), reg, {});
    const auto it =
        std::find_if(used.begin(), used.end(), [](const PluginInfo* i) { return i->id == "rk4"; });
    ASSERT_NE(it, used.end());
    EXPECT_EQ((*it)->file, dir + "/imuconv_plugin_claims_rk4.so");
    EXPECT_EQ((*it)->version, "0.0.1-fixture");
  }
}

}  // namespace
