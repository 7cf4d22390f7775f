// A Kalibr imu.yaml that gives a key twice (issue 22): yaml-cpp keeps both and a lookup finds
// the first, so the second value was ignored in silence (JSON duplicates are refused, with their
// pointer). Refused now, naming the pipeline's pointer, the YAML file, the line of the second
// key and the key, at the top level, under imu0, and in a nested map the reader never looks at.
#include <gtest/gtest.h>

#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"
#include "inline_pipeline.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv::pipeline;
using imuconv::test::TempDir;
using nlohmann::json;

json WithKalibr(const std::string& file) {
  return imuconv::test::OnePreintegrationWithNoise({{"kalibr", file}});
}

/// The issues' text of loading a pipeline whose noise is `yaml` ("" if it loads).
std::string ErrorOf(const TempDir& tmp, const std::string& yaml) {
  tmp.write("imu.yaml", yaml);
  try {
    Pipeline::FromJson(WithKalibr("imu.yaml"), tmp.path() + "/pipeline.json", tmp.path());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

const std::string kFour =
    "gyroscope_noise_density: 1e-4\ngyroscope_random_walk: 1e-5\naccelerometer_noise_density: "
    "1e-3\n"
    "accelerometer_random_walk: 1e-4\n";

TEST(KalibrDuplicateKeys, ASecondValueOfAKeyIsRefusedNamingTheLineAndTheKey) {
  TempDir tmp;
  const std::string at = tmp.path() + "/pipeline.json: /noise/kalibr: " + tmp.path() + "/imu.yaml:";
  ASSERT_EQ(ErrorOf(tmp, kFour), "");
  // Top level: line 5 repeats line 1's key with another value (before: 1e-4 was used).
  std::string e = ErrorOf(tmp, kFour + "gyroscope_noise_density: 5e-2\n");
  EXPECT_NE(e.find(at + "5: duplicate key 'gyroscope_noise_density'"), std::string::npos) << e;
  // Under imu0, as Kalibr's camchain-imucam files nest it.
  std::string nested = "imu0:\n";
  for (std::size_t i = 0, j; i < kFour.size(); i = j + 1) {
    j = kFour.find('\n', i);
    nested += "  " + kFour.substr(i, j - i) + "\n";
  }
  ASSERT_EQ(ErrorOf(tmp, nested), "");
  e = ErrorOf(tmp, nested + "  accelerometer_random_walk: 1e-2\n");
  EXPECT_NE(e.find(at + "6: duplicate key 'accelerometer_random_walk'"), std::string::npos) << e;
  // The same key twice at the top level whose entries are maps: the second imu0 was ignored.
  e = ErrorOf(tmp, nested + "imu0:\n  rostopic: /imu\n");
  EXPECT_NE(e.find(at + "6: duplicate key 'imu0'"), std::string::npos) << e;
}

TEST(KalibrDuplicateKeys, DuplicatesAnywhereInTheDocumentAreRefused) {
  // A map the reader never looks up (T_i_b, a list of maps): a duplicate there is still a file
  // that does not say one thing.
  TempDir tmp;
  const std::string at = tmp.path() + "/pipeline.json: /noise/kalibr: " + tmp.path() + "/imu.yaml:";
  std::string e = ErrorOf(tmp, kFour + "model:\n  name: calibrated\n  name: scale-misalignment\n");
  EXPECT_NE(e.find(at + "7: duplicate key 'name'"), std::string::npos) << e;
  e = ErrorOf(tmp, kFour + "extra:\n  - {a: 1, b: 2, a: 3}\n");
  EXPECT_NE(e.find(at + "6: duplicate key 'a'"), std::string::npos) << e;
  // Keys that differ only in case are different keys.
  EXPECT_EQ(ErrorOf(tmp, kFour + "Update_Rate: 1\nupdate_rate: 200\n"), "");
}

TEST(KalibrDuplicateKeys, AliasesThatExpandBeyondAnyImuFileAreRefused) {
  // Each level doubles the last one: 2^20 values from a few hundred bytes (a "billion laughs").
  TempDir tmp;
  std::string yaml = kFour + "a0: &a0 [x, x]\n";
  for (int k = 1; k <= 20; ++k)
    yaml += "a" + std::to_string(k) + ": &a" + std::to_string(k) + " [*a" + std::to_string(k - 1) +
            ", *a" + std::to_string(k - 1) + "]\n";
  const std::string e = ErrorOf(tmp, yaml);
  EXPECT_NE(e.find("values (YAML aliases?), more than any Kalibr IMU file holds"),
            std::string::npos)
      << e;
}

}  // namespace
