// "noise": {"kalibr": "imu.yaml"}: a Kalibr IMU file gives the same run as its four numbers
// written in the pipeline, and every problem in it is reported with the pipeline's pointer,
// the YAML file and its line.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>

#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"
#include "inline_pipeline.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using imuconv::test::TempDir;
using nlohmann::json;

/// 0.1 s of inline samples and one preintegration whose covariance depends on every density.
json WithNoise(const json& noise) { return imuconv::test::OnePreintegrationWithNoise(noise); }

json RunIn(const std::string& dir, const json& doc) {
  const Pipeline p = Pipeline::FromJson(doc, dir + "/pipeline.json", dir);
  return pipeline::Run(p, imuconv::test::Plugins(), RunOptions{});
}

/// The issues' text of loading `doc` from `dir` ("" if it loads).
std::string LoadError(const std::string& dir, const json& doc) {
  try {
    Pipeline::FromJson(doc, dir + "/pipeline.json", dir);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

const json kEurocNumbers = {{"gyro_noise_density", 1.6968e-04},
                            {"accel_noise_density", 2.0e-3},
                            {"gyro_random_walk", 1.9393e-05},
                            {"accel_random_walk", 3.0e-3}};

TEST(KalibrNoise, TheFileGivesTheSameRunAsItsNumbers) {
  const std::string dir = imuconv::test::DataPath("kalibr");
  const json by_numbers = RunIn(dir, WithNoise(kEurocNumbers));
  for (const char* file :
       {"euroc_imu.yaml", "euroc_imu_result.yaml", "euroc_imu_opencv_header.yaml"}) {
    SCOPED_TRACE(file);
    const json by_file = RunIn(dir, WithNoise({{"kalibr", file}}));
    // The same densities, parsed from the same decimal text: the run is the same to the bit.
    EXPECT_EQ(by_file["noise"], by_numbers["noise"]);
    EXPECT_EQ(by_file["tasks"], by_numbers["tasks"]);
    // And the covariance really depends on them (else the equality would prove nothing).
    const json other = RunIn(dir, WithNoise({{"gyro_noise_density", 1.6968e-04},
                                             {"accel_noise_density", 2.0e-3},
                                             {"gyro_random_walk", 1.9393e-05},
                                             {"accel_random_walk", 3.1e-3}}));
    EXPECT_NE(by_file["tasks"], other["tasks"]);
  }
}

TEST(KalibrNoise, TheFileIsAnInputAnOutputMayNotReplace) {
  const std::string dir = imuconv::test::DataPath("kalibr");
  const Pipeline p =
      Pipeline::FromJson(WithNoise({{"kalibr", "euroc_imu.yaml"}}), dir + "/pipeline.json", dir);
  const auto files = p.input_files();
  EXPECT_NE(std::find(files.begin(), files.end(), dir + "/euroc_imu.yaml"), files.end());
}

TEST(KalibrNoise, ProblemsNameThePointerTheFileAndTheLine) {
  TempDir tmp;
  const std::string d = tmp.path();
  const auto error_of = [&](const std::string& yaml) {
    tmp.write("imu.yaml", yaml);
    return LoadError(d, WithNoise({{"kalibr", "imu.yaml"}}));
  };
  // "FILE:LINE: " for a problem on a line, "FILE: " for one about the whole file.
  const std::string at = d + "/pipeline.json: /noise/kalibr: " + d + "/imu.yaml:";
  const std::string whole = d + "/pipeline.json: /noise/kalibr: " + d + "/imu.yaml: ";
  const std::string complete =
      "gyroscope_noise_density: 1e-4\ngyroscope_random_walk: 1e-5\naccelerometer_noise_density: "
      "1e-3\n"
      "accelerometer_random_walk: 1e-4\n";
  EXPECT_EQ(error_of(complete), "");

  std::string e = error_of(
      "gyroscope_noise_density: 1e-4\ngyroscope_random_walk: 1e-5\naccelerometer_noise_density: "
      "1e-3\n");
  EXPECT_NE(e.find(at + "1: accelerometer_random_walk: required key is missing"), std::string::npos)
      << e;
  e = error_of(complete + "update_rate: fast\n");
  EXPECT_NE(e.find(at + "5: update_rate: expected a number"), std::string::npos) << e;
  e = error_of(
      "gyroscope_noise_density: 1e-4\ngyroscope_random_walk: -1e-5\naccelerometer_noise_density: "
      "1e-3\n"
      "accelerometer_random_walk: 1e-4\n");
  EXPECT_NE(
      e.find(at + "2: gyroscope_random_walk: expected a finite non-negative number, found '-1e-5'"),
      std::string::npos)
      << e;
  e = error_of(
      "gyroscope_noise_density: .nan\ngyroscope_random_walk: 1e-5\naccelerometer_noise_density: "
      "1e-3\n"
      "accelerometer_random_walk: 1e-4\n");
  EXPECT_NE(e.find(at + "1: gyroscope_noise_density: expected a finite non-negative number"),
            std::string::npos)
      << e;
  e = error_of(complete + "update_rate: 0\n");
  EXPECT_NE(e.find(at + "5: update_rate: expected a rate > 0 Hz"), std::string::npos) << e;
  e = error_of("gyroscope_noise_density: [1e-4\n");
  EXPECT_NE(e.find(at), std::string::npos) << e;
  EXPECT_NE(e.find("not valid YAML"), std::string::npos) << e;
  e = error_of("imu0:\n  gyroscope_noise_density: 1\nimu1:\n  gyroscope_noise_density: 2\n");
  EXPECT_NE(e.find(whole + "several IMUs (imu0, imu1): give a file with one IMU's noise"),
            std::string::npos)
      << e;
  e = error_of("- 1\n- 2\n");
  EXPECT_NE(e.find(at + "1: expected a YAML mapping of Kalibr IMU keys"), std::string::npos) << e;
  e = error_of("rostopic: /imu0\n");
  EXPECT_NE(e.find(whole + "no Kalibr IMU keys"), std::string::npos) << e;
  e = error_of("");
  EXPECT_NE(e.find(whole + "expected a YAML mapping"), std::string::npos) << e;
}

TEST(KalibrNoise, HostileFilesAreRefusedWithoutHangOrCrash) {
  TempDir tmp;
  const std::string d = tmp.path();
  // Missing.
  std::string e = LoadError(d, WithNoise({{"kalibr", "absent.yaml"}}));
  EXPECT_NE(e.find("/noise/kalibr: " + d + "/absent.yaml: cannot open the file for reading"),
            std::string::npos)
      << e;
  // A FIFO with no writer: refused, not waited on.
  ASSERT_EQ(mkfifo(tmp.file("fifo.yaml").c_str(), 0600), 0);
  e = LoadError(d, WithNoise({{"kalibr", "fifo.yaml"}}));
  EXPECT_NE(e.find("/noise/kalibr: " + d + "/fifo.yaml: is a FIFO, not a regular file"),
            std::string::npos)
      << e;
  // Larger than 64 KiB: refused before it is parsed.
  tmp.write("big.yaml", "# " + std::string(70000, 'x') + "\n");
  e = LoadError(d, WithNoise({{"kalibr", "big.yaml"}}));
  EXPECT_NE(e.find("is larger than 64 KiB"), std::string::npos) << e;
  // Nesting 30 000 deep (60 KiB): yaml-cpp's depth guard refuses it; no stack overflow.
  tmp.write("deep.yaml", std::string(30000, '[') + std::string(30000, ']') + "\n");
  e = LoadError(d, WithNoise({{"kalibr", "deep.yaml"}}));
  EXPECT_NE(e.find("/noise/kalibr: " + d + "/deep.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("levels deep, deeper than any IMU file"), std::string::npos) << e;
  // Not a string, and unknown keys beside "kalibr".
  e = LoadError(d, WithNoise({{"kalibr", 3}}));
  EXPECT_NE(e.find("/noise/kalibr: expected a string"), std::string::npos) << e;
  e = LoadError(d, WithNoise({{"kalibr", "imu.yaml"}, {"gyro_noise_density", 1}}));
  EXPECT_NE(e.find("/noise/gyro_noise_density: unknown key"), std::string::npos) << e;
}

}  // namespace
