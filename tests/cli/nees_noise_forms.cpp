// imuconv nees --noise FILE takes every form the pipeline's /noise takes, read by the pipeline's
// own reader: a pipeline whose /noise is {"kalibr": "imu.yaml"} (the path relative to that
// pipeline's directory, not to the working directory), and a Kalibr file whose extension is in
// upper case. Each must give the document the same densities give as a JSON noise object, bit
// for bit: the same four doubles reach the same code (the yaml holds the datasheet's digits).
// A kalibr path that does not exist is refused naming the file and /noise/kalibr.
//
// Each run is 40 windows of 0.5 s on the EuRoC slice: well under a second in Release.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "euroc_slice.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;
using nlohmann::json;

const std::string kNoiseFormsKalibr = DataPath("kalibr/euroc_imu.yaml");

std::string NoiseFormArgs(const std::string& noise_path) {
  return "--imu " + ShellQuote(kEurocSliceImu) + " --ground-truth " +
         ShellQuote(kEurocSliceGroundTruth) + " --noise " + ShellQuote(noise_path) +
         " --windows 0.5 --method rk4";
}

/// A pipeline over the slice whose /noise is `noise` (the slice's files by absolute path).
json PipelineWithNoiseForm(const json& noise) {
  json p = NeesPipeline({{"format", "euroc"}, {"path", kEurocSliceImu}});
  p["noise"] = noise;
  return p;
}

TEST(NeesNoiseForms, PipelineWithKalibrNoiseAndUpperCaseYamlAreRead) {
  const TempDir tmp;
  const json from_json =
      RunImuconvJson("nees", NoiseFormArgs(tmp.write("noise.json", kEurocNoise.dump())), tmp);
  ASSERT_TRUE(from_json.is_object());

  // The pipeline and its yaml in a directory of their own; the command does not run there, so the
  // relative "k.yaml" is found only if it is resolved against the pipeline's directory.
  std::filesystem::create_directories(tmp.file("calib"));
  std::filesystem::copy_file(kNoiseFormsKalibr, tmp.file("calib/k.yaml"));
  const std::string pipeline =
      tmp.write("calib/kal.json", PipelineWithNoiseForm({{"kalibr", "k.yaml"}}).dump());
  EXPECT_EQ(RunImuconvJson("nees", NoiseFormArgs(pipeline), tmp), from_json);

  // NOISE.YAML is a Kalibr file, not JSON.
  std::filesystem::copy_file(kNoiseFormsKalibr, tmp.file("NOISE.YAML"));
  EXPECT_EQ(RunImuconvJson("nees", NoiseFormArgs(tmp.file("NOISE.YAML")), tmp), from_json);

  // The kalibr form alone, as a noise file (not inside a pipeline), is the same form.
  const std::string bare = tmp.write("calib/bare.json", json{{"kalibr", "k.yaml"}}.dump());
  EXPECT_EQ(RunImuconvJson("nees", NoiseFormArgs(bare), tmp), from_json);

  // A kalibr file that is not there: exit 2, naming the --noise file, the pointer and the yaml.
  const std::string missing =
      tmp.write("calib/missing.json", PipelineWithNoiseForm({{"kalibr", "absent.yaml"}}).dump());
  const CommandResult r = RunImuconv("nees " + NoiseFormArgs(missing), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "missing.json") && Has(r.err, "/noise/kalibr") &&
              Has(r.err, "absent.yaml"))
      << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace
