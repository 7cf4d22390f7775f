// A list of ids whose items become keys of an output object ("conventions" of a preintegrate
// task, "first_order_charts" of a bias update) must not repeat one: the output would hold a
// key twice, which is no JSON any reader takes (imuconv's own refuses it), and the NPZ writer
// found it only after the work was done. Refused when the pipeline is read, at the item.
#include <gtest/gtest.h>

#include "imuconv/pipeline/pipeline.h"
#include "inline_pipeline.h"
#include "issue_at.h"
#include "pipeline_test_util.h"

// A named namespace, not an anonymous one: the tests are compiled in unity batches, where
// this file's helpers and using-directives must not meet another file's.
namespace ids_listed_twice_test {
using namespace imuconv;
using namespace imuconv::pipeline;
using namespace imuconv::test;
using nlohmann::json;

/// One preintegration over 0.1 s expressed in `conventions`, and a bias update of it with
/// first-order charts `charts`.
json PreintegrationAndBiasUpdate(const json& conventions, const json& charts) {
  json doc = OnePreintegrationWithNoise(TacticalNoiseDensities());
  doc["tasks"][0]["conventions"] = conventions;
  doc["tasks"].push_back({{"type", "bias_update"},
                          {"name", "bu"},
                          {"measurements", "pre"},
                          {"bias", {{"delta_bg", {0.001, 0, 0}}}},
                          {"first_order_charts", charts}});
  return doc;
}

TEST(IdsListedTwice, DistinctListsAreRead) {
  EXPECT_TRUE(ReadingIssues(PreintegrationAndBiasUpdate({"gtsam_manifold", "gtsam_tangent"},
                                                        {"preint_reference", "gtsam_manifold"}))
                  .empty());
}

TEST(IdsListedTwice, ARepeatedConventionIsRefusedAtTheRepeat) {
  const auto is = ReadingIssues(PreintegrationAndBiasUpdate(
      {"gtsam_manifold", "gtsam_tangent", "gtsam_manifold"}, json::array()));
  EXPECT_ISSUE(is, "/tasks/0/conventions/2", "'gtsam_manifold' is listed twice");
  EXPECT_EQ(is.size(), 1u);
}

TEST(IdsListedTwice, ARepeatedFirstOrderChartIsRefusedAtTheRepeat) {
  const auto is = ReadingIssues(PreintegrationAndBiasUpdate(
      json::array(), {"preint_reference", "gtsam_manifold", "preint_reference"}));
  EXPECT_ISSUE(is, "/tasks/1/first_order_charts/2", "'preint_reference' is listed twice");
  EXPECT_EQ(is.size(), 1u);
}

TEST(IdsListedTwice, TheCommandExitsTwoAndWritesNeitherJsonNorNpz) {
  TempDir tmp;
  const std::string p = tmp.write(
      "d.json",
      PreintegrationAndBiasUpdate({"gtsam_manifold", "gtsam_manifold"}, {"preint_reference"})
          .dump());
  for (const std::string out : {"d.out.json", "d.npz"}) {
    const CommandResult r =
        RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(tmp.file(out)), tmp);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(p + ": /tasks/0/conventions/1: 'gtsam_manifold' is listed twice"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(tmp.file(out))) << out;
  }
}

}  // namespace ids_listed_twice_test
