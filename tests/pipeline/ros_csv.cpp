// The ROS route: `rostopic echo -b BAG -p /imu > imu.csv` writes a CSV whose header names every
// field of sensor_msgs/Imu; a pipeline reads it by those names, with the message stamps in
// nanoseconds. Checked against the same samples given inline.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"
#include "inline_pipeline.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using nlohmann::json;

const json kNoise = test::NoiseDensities(1.7e-4, 2e-3, 2e-5, 3e-3);

json Tasks() {
  return {{{"type", "preintegrate"},
           {"name", "pre"},
           {"method", {{"preintegrator", "manifold"}}},
           {"keyframes", {0.0, 0.05, 0.1}}}};
}

TEST(RosCsv, RostopicEchoColumnsReadByName) {
  const std::string dir = imuconv::test::DataPath("ros");
  const json by_name = {{"noise", kNoise},
                        {"imu",
                         {{"format", "csv"},
                          {"path", "imu_rostopic_echo.csv"},
                          {"header_rows", 1},
                          {"time_unit", "ns"},
                          {"columns",
                           {{"t", "field.header.stamp"},
                            {"wx", "field.angular_velocity.x"},
                            {"wy", "field.angular_velocity.y"},
                            {"wz", "field.angular_velocity.z"},
                            {"ax", "field.linear_acceleration.x"},
                            {"ay", "field.linear_acceleration.y"},
                            {"az", "field.linear_acceleration.z"}}}}},
                        {"tasks", Tasks()}};
  const json out = pipeline::Run(Pipeline::FromJson(by_name, dir + "/pipeline.json", dir),
                                 test::Plugins(), RunOptions{});

  // The same samples, parsed here from the file's text by column position, given inline with
  // times relative to the first stamp (the csv reader's origin).
  std::ifstream in(dir + "/imu_rostopic_echo.csv");
  std::string line;
  std::getline(in, line);
  json samples = json::array();
  long long t0 = -1;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream s(line);
    for (std::string x; std::getline(s, x, ',');) f.push_back(x);
    ASSERT_EQ(
        f.size(),
        41u);  // 4 header fields, orientation 4 + 9, angular velocity 3 + 9, acceleration 3 + 9
    const long long stamp = std::stoll(f[2]);
    if (t0 < 0) t0 = stamp;
    // Angular velocity x..z at 17..19, linear acceleration at 29..31 (each after 9 covariances).
    samples.push_back({static_cast<double>(stamp - t0) * 1e-9, std::stod(f[17]), std::stod(f[18]),
                       std::stod(f[19]), std::stod(f[29]), std::stod(f[30]), std::stod(f[31])});
  }
  const json inline_doc = {
      {"noise", kNoise}, {"imu", {{"format", "inline"}, {"samples", samples}}}, {"tasks", Tasks()}};
  const json ref = pipeline::Run(Pipeline::FromJson(inline_doc, dir + "/pipeline.json", dir),
                                 test::Plugins(), RunOptions{});
  ASSERT_EQ(out["tasks"][0]["measurements"].size(), 2u);
  // Times: the csv keeps the stamps exactly (integer ns relative to the first), the inline
  // copy went through a double of seconds, so the two runs differ by the round-off of those
  // times only: measured 6e-17 in dv (|dv| ~ 1 m/s), 4e-18 in dp, 5e-23 in cov. Bounds: 1e-15
  // (ten ulps of 0.1) for the increments, 1e-12 of the largest entry for the covariance.
  for (std::size_t k = 0; k < 2; ++k) {
    const json& a = out["tasks"][0]["measurements"][k];
    const json& b = ref["tasks"][0]["measurements"][k];
    EXPECT_NEAR(a["dt"].get<double>(), b["dt"].get<double>(), 1e-15);
    for (const char* key : {"dp", "dv"})
      EXPECT_LT((test::JsonMatrix(a["delta"][key]) - test::JsonMatrix(b["delta"][key]))
                    .cwiseAbs()
                    .maxCoeff(),
                1e-15)
          << key;
    const Eigen::MatrixXd ca = test::JsonMatrix(a["cov"]["matrix"]),
                          cb = test::JsonMatrix(b["cov"]["matrix"]);
    EXPECT_LT((ca - cb).cwiseAbs().maxCoeff(), 1e-12 * cb.cwiseAbs().maxCoeff());
  }
}

}  // namespace
