// The check task seen from the pipeline library alone (which imuconv check links, never the
// reverse): without the evaluation apps/check registers, a check task is still parsed and its
// input checked before any task runs, and running it fails by name and pointer, with nothing
// computed in its place. (What it computes is tested through the command in
// tests/cli/check_pipeline.cpp.)
#include <gtest/gtest.h>

#include <string>

#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/pipeline_data.h"
#include "imuconv_test.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;

const std::string kCase =
    std::string(IMUCONV_TEST_DATA_DIR) + "/pipeline_cases/accept/check_task.json";

TEST(CheckTaskWithoutEvaluator, IsCheckedAndThenFailsByName) {
  ASSERT_EQ(GetCheckEvaluator(), nullptr);  // nothing in this program registers one
  const Pipeline p = Pipeline::Load(kCase);
  RunOptions options;
  options.threads = 1;
  options.check_only = true;
  EXPECT_NO_THROW(RunToText(p, test::Plugins(), options, [](std::string_view) {}));
  options.check_only = false;
  const std::string m = test::MessageOf<Error>(
      [&] { RunToText(p, test::Plugins(), options, [](std::string_view) {}); });
  ASSERT_FALSE(m.empty()) << "a check task ran without imuconv check's evaluation";
  EXPECT_NE(m.find("check_task.json"), std::string::npos) << m;
  EXPECT_NE(m.find("/tasks/0"), std::string::npos) << m;
  EXPECT_NE(m.find("cannot run a check task"), std::string::npos) << m;
}

TEST(CheckTaskWithoutEvaluator, ItsMeasurementsFileIsAnInputOfTheRun) {
  const Pipeline p = Pipeline::Load(kCase);
  bool found = false;
  for (const auto& f : p.input_files())
    found |= f.find("check_measurements.json") != std::string::npos;
  EXPECT_TRUE(found);
}

}  // namespace
