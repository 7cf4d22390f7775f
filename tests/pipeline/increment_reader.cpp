// One reader for the increment form. A convert task's "increment" and a measurements file's
// "delta" were read by two functions with different rules (one refused q_wxyz together with R
// and knew no rotation_angle_deg; the other took both, and q_wxyz silently won). Both paths
// now go through IncrementFromJson: every input either path accepted is read by both to the
// same increment, bit for bit, and what either refused is refused by both, with the same
// message at the same place in each document.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "../../apps/pipeline/src/forms/increment.h"
#include "imuconv/pipeline/measurement.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"
#include "inline_pipeline.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using nlohmann::json;

const char* kIncrementFile = "increment_reader_test.json";

json Zeros(int rows, int cols) {
  json m = json::array();
  for (int i = 0; i < rows; ++i)
    m.push_back(std::vector<double>(static_cast<std::size_t>(cols), 0.0));
  return m;
}

json Identity15(double s) {
  json m = Zeros(15, 15);
  for (int i = 0; i < 15; ++i) m[i][i] = s;
  return m;
}

/// A rotation of 0.3 rad about (1, 2, 2)/3, as a quaternion and as a matrix (both to 17
/// digits, so they agree far inside the 1e-6 deg rule).
const json kQ = {std::cos(0.15), std::sin(0.15) / 3, 2 * std::sin(0.15) / 3,
                 2 * std::sin(0.15) / 3};
json MatrixOfQ() {
  const Mat3 R = Eigen::Quaterniond(kQ[0].get<double>(), kQ[1].get<double>(), kQ[2].get<double>(),
                                    kQ[3].get<double>())
                     .toRotationMatrix();
  json m = json::array();
  for (int i = 0; i < 3; ++i) m.push_back({R(i, 0), R(i, 1), R(i, 2)});
  return m;
}

/// Path 1: a convert task's "increment", as the task writes it back.
json ViaConvertTask(const json& increment) {
  const json doc = {{"noise", test::NoiseDensities(1e-3, 1e-2, 1e-5, 1e-4)},
                    {"tasks",
                     {{{"type", "convert"},
                       {"name", "c"},
                       {"what", "increment_jacobian"},
                       {"from", "preint_reference"},
                       {"to", "gtsam_tangent"},
                       {"increment", increment}}}}};
  const Pipeline p = Pipeline::FromJson(doc, kIncrementFile, IMUCONV_SOURCE_DIR);
  return pipeline::Run(p, imuconv::test::Plugins(), {})["tasks"][0]["increment"];
}

/// Path 2: a measurements file's "delta", read, then written with the same writer.
json ViaMeasurementFile(const json& delta) {
  const json doc = {
      {"measurements",
       {{{"dt", 0.1},
         {"bias_estimate", {{"bg", {0, 0, 0}}, {"ba", {0, 0, 0}}}},
         {"delta", delta},
         {"J_bias", {{"convention", "preint_reference"}, {"matrix", Zeros(9, 6)}}},
         {"cov", {{"convention", "preint_reference"}, {"matrix", Identity15(1e-6)}}}}}}};
  const auto records =
      ReadMeasurementDocument(doc, kIncrementFile, imuconv::test::Plugins(), std::nullopt);
  EXPECT_EQ(records.size(), 1u);
  std::string text;
  JsonWriter w(text);
  WriteIncrement(w, records.at(0).m.delta);
  return json::parse(text);
}

/// The message of the first problem a path reports, without the file and the pointer up to
/// the increment object (which differ between the two documents).
std::string Refusal(const std::function<void()>& f, const std::string& prefix) {
  try {
    f();
  } catch (const ConfigError& e) {
    if (e.issues().empty()) return "no issue";
    const Issue& i = e.issues().front();
    if (i.pointer.compare(0, prefix.size(), prefix) != 0)
      return "at " + i.pointer + ": " + i.message;
    return i.pointer.substr(prefix.size()) + ": " + i.message;
  }
  return "accepted";
}

TEST(IncrementReader, WhatEitherOldPathAcceptedBothReadAlike) {
  const json dp = {0.1, -0.2, 0.05}, dv = {1.0, 0.5, -0.25};
  std::vector<json> accepted = {
      // the convert task's old reader: q_wxyz or R, dbg/dba optional
      {{"q_wxyz", kQ}, {"dp", dp}, {"dv", dv}},
      {{"R", MatrixOfQ()}, {"dp", dp}, {"dv", dv}},
      {{"q_wxyz", kQ}, {"dp", dp}, {"dv", dv}, {"dbg", {1e-3, 0, 0}}, {"dba", {0, -2e-3, 0}}},
      // the measurement file's old reader: also both, and rotation_angle_deg
      {{"q_wxyz", kQ}, {"R", MatrixOfQ()}, {"dp", dp}, {"dv", dv}},
      {{"q_wxyz", kQ}, {"dp", dp}, {"dv", dv}, {"rotation_angle_deg", 0.3 * 180 / M_PI}},
      {{"q_wxyz", {1, 0, 0, 0}}, {"dp", {0, 0, 0}}, {"dv", {0, 0, 0}}},
  };
  for (const json& d : accepted) {
    SCOPED_TRACE(d.dump());
    const json a = ViaConvertTask(d), b = ViaMeasurementFile(d);
    EXPECT_EQ(a, b);  // every number the same (written shortest round-trip, so bit for bit)
    // And what was given is what was read (to the 1e-12 of the quaternion's round trip).
    EXPECT_EQ(a["dp"], d["dp"]);
    EXPECT_EQ(a["dv"], d["dv"]);
    EXPECT_EQ(a["dbg"], d.value("dbg", json{0.0, 0.0, 0.0}));
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(a["q_wxyz"][k].get<double>(),
                  d.contains("q_wxyz") ? d["q_wxyz"][k].get<double>() : kQ[k].get<double>(), 1e-12);
  }
}

TEST(IncrementReader, WhatEitherOldPathRefusedBothRefuseAlike) {
  const json dp = {0.1, -0.2, 0.05}, dv = {1.0, 0.5, -0.25};
  json bad_R = MatrixOfQ();
  bad_R[0][0] = bad_R[0][0].get<double>() + 1e-3;
  json other_R = json::array({json{1, 0, 0}, json{0, 1, 0}, json{0, 0, 1}});
  const std::vector<std::pair<json, std::string>> refused = {
      {{{"dp", dp}, {"dv", dv}}, "/q_wxyz: required key is missing (give q_wxyz or R)"},
      {{{"q_wxyz", {1, 0, 0, 0.1}}, {"dp", dp}, {"dv", dv}}, "/q_wxyz: expected a unit quaternion"},
      {{{"R", bad_R}, {"dp", dp}, {"dv", dv}}, "/R: expected a rotation matrix"},
      {{{"q_wxyz", kQ}, {"R", other_R}, {"dp", dp}, {"dv", dv}},
       "/R: R and q_wxyz disagree by 17.18"},
      {{{"q_wxyz", kQ}, {"dp", dp}, {"dv", dv}, {"rotation_angle_deg", 17.0}},
       "/rotation_angle_deg: rotation_angle_deg = 17 does not match the rotation's angle"},
      {{{"q_wxyz", kQ}, {"dp", dp}}, "/dv: required key is missing"},
      {{{"q_wxyz", kQ}, {"dp", dp}, {"dv", dv}, {"dq", 1}}, "/dq: unknown key"},
  };
  // Not a structured binding: a lambda may capture one only from C++20 on (clang 14 refuses).
  for (const auto& entry : refused) {
    const json& d = entry.first;
    const std::string& expected = entry.second;
    SCOPED_TRACE(d.dump());
    const std::string a = Refusal([&] { ViaConvertTask(d); }, "/tasks/0/increment");
    const std::string b = Refusal([&] { ViaMeasurementFile(d); }, "/measurements/0/delta");
    EXPECT_EQ(a, b);
    EXPECT_EQ(a.compare(0, expected.size(), expected), 0) << a;
  }
}

}  // namespace
