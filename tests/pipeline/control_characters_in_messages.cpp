// Strings from a pipeline reach its error messages escaped (printable.h): an ESC, a BEL or a
// newline in a task name, a time, a delimiter, a state given as a string or a matrix's
// convention would otherwise rewrite the user's terminal or fake a line of output.
#include <gtest/gtest.h>

#include <algorithm>

#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"
#include "inline_pipeline.h"
#include "issue_at.h"
#include "pipeline_test_util.h"

// A named namespace, not an anonymous one: the tests are compiled in unity batches, where
// this file's helpers and using-directives must not meet another file's.
namespace control_characters_in_messages_test {
using namespace imuconv;
using namespace imuconv::pipeline;
using namespace imuconv::test;
using nlohmann::json;

// ESC [31m (red), a newline, a BEL: each must reach the message as \x1b, \n, \x07.
const std::string kHostile = "a\x1b[31mb\nc\x07";
const std::string kEscaped = "a\\x1b[31mb\\nc\\x07";

/// The issues of reading and checking `doc` (empty if it runs).
std::vector<Issue> Issues(const json& doc) {
  try {
    const pipeline::Pipeline p =
        pipeline::Pipeline::FromJson(doc, kMemPipelineFile, IMUCONV_SOURCE_DIR);
    pipeline::Run(p, Plugins(), RunOptions{});
  } catch (const ConfigError& e) {
    // what() joins the issues: no control character (but the newlines between issues).
    const std::string w = e.what();
    EXPECT_TRUE(std::none_of(w.begin(), w.end(), [](char c) {
      return static_cast<unsigned char>(c) < 0x20 && c != '\n';
    })) << w;
    EXPECT_EQ(w.find("b\nc"), std::string::npos) << w;
    return e.issues();
  }
  return {};
}

json CsvImu(const json& extra) {
  json imu = {
      {"format", "csv"},
      {"path", SourcePath("examples/data/generic_imu_seconds.csv")},
      {"header_rows", 1},
      {"delimiter", ";"},
      {"time_unit", "s"},
      {"columns", {{"t", 0}, {"ax", 1}, {"ay", 2}, {"az", 3}, {"wx", 4}, {"wy", 5}, {"wz", 6}}}};
  imu.update(extra);
  return imu;
}

TEST(ControlCharactersInMessages, TaskName) {
  json doc = OnePreintegrationWithNoise(TacticalNoiseDensities());
  doc["tasks"][0]["name"] = kHostile;
  EXPECT_ISSUE(Issues(doc), "/tasks/0/name", "found '" + kEscaped + "'");
}

TEST(ControlCharactersInMessages, TimeOriginGivenAsAString) {
  json doc = OnePreintegrationWithNoise(TacticalNoiseDensities());
  doc["imu"] = CsvImu({{"time_origin", kHostile}});
  EXPECT_ISSUE(Issues(doc), "/imu/time_origin",
               "expected a decimal time, found '" + kEscaped + "'");
}

TEST(ControlCharactersInMessages, Delimiter) {
  json doc = OnePreintegrationWithNoise(TacticalNoiseDensities());
  doc["imu"] = CsvImu({{"delimiter", kHostile}});
  EXPECT_ISSUE(Issues(doc), "/imu/delimiter", "found '" + kEscaped + "'");
  doc["imu"] = CsvImu({{"delimiter", "\n"}});
  EXPECT_ISSUE(Issues(doc), "/imu/delimiter", "found '\\n'");
}

TEST(ControlCharactersInMessages, StateGivenAsAString) {
  json doc =
      TenthSecondAt100HzRunning(json::array({Rk4PropagationOverTenthSecond("prop", kHostile)}));
  EXPECT_ISSUE(Issues(doc), "/tasks/0/start/state", "found the string '" + kEscaped + "'");
}

TEST(ControlCharactersInMessages, MatrixConvention) {
  json doc = TenthSecondAt100HzRunning(
      {{{"type", "convert"},
        {"name", "cv"},
        {"what", "state_covariance"},
        {"from", "left"},
        {"to", "gtsam_navstate"},
        {"state", UnitSpeedStartState()},
        {"matrix", {{"convention", kHostile}, {"sigma", std::vector<double>(15, 1.0)}}}}});
  EXPECT_ISSUE(Issues(doc), "/tasks/0/matrix/convention",
               "the matrix is in '" + kEscaped + "' but \"from\" is 'left'");
}

}  // namespace control_characters_in_messages_test
