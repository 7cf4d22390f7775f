// Pose-only ground truth (TUM, EuRoC vicon0), with the sensor's pose in the body T_BS.
//
// The files are made in the test from the examples' full-state ground truth (the same poses
// written the other way), so every error computed against them must be the one computed
// against the full state: exactly for TUM and vicon0 (the same numbers, the times converted
// exactly), and to rounding through T_BS (sensor poses written with 17 digits, then mapped
// back: |d| ~ 1e-15 relative; 1e-9 covers the interpolation of the mapped poses, which is the
// same to rounding). What a pose cannot give (velocity, biases, a start state) is refused at
// its JSON pointer, never filled in with zeros.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "imuconv/so3.h"
#include "number_text.h"
#include "pipeline_test_util.h"

namespace imuconv::test {
namespace {

using nlohmann::json;

struct GtRow {
  std::string t_ns;
  double v[16];  // p xyz, q wxyz, v xyz, bg xyz, ba xyz
};

std::vector<GtRow> ReadFullGroundTruth() {
  std::ifstream in(SourcePath("examples/data/V1_01_easy_groundtruth_vicon2gt_slice.csv"));
  std::vector<GtRow> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string field;
    GtRow r;
    std::getline(ss, r.t_ns, ',');
    for (double& x : r.v) {
      std::getline(ss, field, ',');
      x = std::stod(field);
    }
    rows.push_back(r);
  }
  return rows;
}

/// TUM text of the rows' poses: "sec.nanosec x y z qx qy qz qw" (the stamps exactly).
std::string Tum(const std::vector<GtRow>& rows) {
  std::string s = "# timestamp tx ty tz qx qy qz qw\n";
  for (const auto& r : rows) {
    const std::string sec = r.t_ns.substr(0, r.t_ns.size() - 9),
                      frac = r.t_ns.substr(r.t_ns.size() - 9);
    s += sec + "." + frac + " " + Num17(r.v[0]) + " " + Num17(r.v[1]) + " " + Num17(r.v[2]) + " " +
         Num17(r.v[4]) + " " + Num17(r.v[5]) + " " + Num17(r.v[6]) + " " + Num17(r.v[3]) + "\n";
  }
  return s;
}

/// EuRoC vicon0 text of the rows' own poses (the same numbers, 17 digits).
std::string Vicon0Copy(const std::vector<GtRow>& rows) {
  std::string s =
      "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z "
      "[]\n";
  for (const auto& r : rows) {
    s += r.t_ns;
    for (int i = 0; i < 7; ++i) s += "," + Num17(r.v[i]);
    s += "\n";
  }
  return s;
}

/// EuRoC vicon0 text of the poses of a sensor S at T_BS = (R_BS, p_BS) on the body:
/// T_RS = T_RB T_BS.
std::string Vicon0(const std::vector<GtRow>& rows, const Mat3& R_BS, const Vec3& p_BS) {
  std::string s =
      "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z "
      "[]\n";
  for (const auto& r : rows) {
    const Mat3 R_RB = so3::FromQuaternionWxyz(r.v[3], r.v[4], r.v[5], r.v[6]);
    const Vec3 p_RS = Vec3(r.v[0], r.v[1], r.v[2]) + R_RB * p_BS;
    const Eigen::Vector4d q = so3::ToQuaternionWxyz(R_RB * R_BS);
    s += r.t_ns + "," + Num17(p_RS.x()) + "," + Num17(p_RS.y()) + "," + Num17(p_RS.z()) + "," +
         Num17(q[0]) + "," + Num17(q[1]) + "," + Num17(q[2]) + "," + Num17(q[3]) + "\n";
  }
  return s;
}

/// The keyframes example with the start state and bias given (the first ground-truth row),
/// over 2 s, chained: what a pose-only ground truth allows.
json PoseGroundTruthPipeline(const std::vector<GtRow>& rows, const json& ground_truth) {
  json p = json::parse(ReadText(SourcePath("examples/euroc_v1_01_keyframes.json")));
  p.erase("$schema");
  p["imu"]["path"] = SourcePath("examples/data/V1_01_easy_imu0_slice.csv");
  p["ground_truth"] = ground_truth;
  const double* v = rows.front().v;
  const json bias = {{"bg", {v[10], v[11], v[12]}}, {"ba", {v[13], v[14], v[15]}}};
  const json state = {{"p", {v[0], v[1], v[2]}},
                      {"q_wxyz", {v[3], v[4], v[5], v[6]}},
                      {"v", {v[7], v[8], v[9]}},
                      {"bg", {v[10], v[11], v[12]}},
                      {"ba", {v[13], v[14], v[15]}}};
  for (auto& t : p["tasks"]) {
    if (t["type"] == "preintegrate") {
      t["bias"] = bias;
      t["keyframes"] = {{"start", 0.0}, {"end", 2.0}, {"step", 0.1}};
    } else {
      t["start"] = {{"state", state}};
    }
  }
  return p;
}

/// Every step's ground-truth comparison of the pipeline's output.
std::vector<json> Comparisons(const TempDir& tmp, const json& pipeline, const std::string& name) {
  const std::string path = tmp.write(name + ".json", pipeline.dump());
  const CommandResult r = RunImuconv(
      "run " + ShellQuote(path) + " -o " + ShellQuote(tmp.file(name + ".out.json")), tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::vector<json> out;
  if (r.exit_code != 0) return out;
  const json doc = json::parse(ReadText(tmp.file(name + ".out.json")));
  for (const auto& t : doc["tasks"])
    if (t.contains("steps"))
      for (const auto& s : t["steps"]) out.push_back(s.at("ground_truth"));
  return out;
}

/// The comparisons of the pipeline over `rows` against the full-state ground truth file they
/// were read from (the reference the pose formats are compared with).
std::vector<json> FullStateComparisons(const TempDir& tmp, const std::vector<GtRow>& rows) {
  return Comparisons(
      tmp,
      PoseGroundTruthPipeline(
          rows, {{"format", "euroc"},
                 {"path", SourcePath("examples/data/V1_01_easy_groundtruth_vicon2gt_slice.csv")}}),
      "full");
}

TEST(PoseGroundTruth, TumAndVicon0GiveTheFullStateErrorsExactly) {
  TempDir tmp;
  const auto rows = ReadFullGroundTruth();
  ASSERT_GT(rows.size(), 40u);
  const auto full = FullStateComparisons(tmp, rows);
  const auto tum = Comparisons(
      tmp,
      PoseGroundTruthPipeline(rows, {{"format", "tum"}, {"path", tmp.write("gt.tum", Tum(rows))}}),
      "tum");
  const auto vicon = Comparisons(
      tmp,
      PoseGroundTruthPipeline(
          rows, {{"format", "euroc_pose"}, {"path", tmp.write("vicon0.csv", Vicon0Copy(rows))}}),
      "vicon");
  ASSERT_EQ(full.size(), 40u);  // two tasks of 20 steps
  for (const auto* poses : {&tum, &vicon}) {
    ASSERT_EQ(poses->size(), full.size());
    for (std::size_t k = 0; k < full.size(); ++k) {
      const json& f = full[k];
      const json& g = (*poses)[k];
      // The TUM file holds the 17-digit numbers of the full file's 6-digit ones, the same doubles.
      EXPECT_EQ(g.at("position_error_m").get<double>(), f.at("position_error_m").get<double>())
          << k;
      EXPECT_EQ(g.at("rotation_error_deg").get<double>(), f.at("rotation_error_deg").get<double>())
          << k;
      EXPECT_EQ(g.at("pose").at("p"), f.at("state").at("p")) << k;
      // Nothing a pose cannot tell.
      EXPECT_FALSE(g.contains("velocity_error_mps") || g.contains("error_left") ||
                   g.contains("state"))
          << g.dump();
    }
  }
}

TEST(PoseGroundTruth, SensorPosesAreMappedToTheBodyByT_BS) {
  TempDir tmp;
  const auto rows = ReadFullGroundTruth();
  const Mat3 R_BS = so3::Exp(Vec3(0.3, -1.2, 2.0));
  const Vec3 p_BS(0.0690, -0.0278, -0.1240);
  json T = json::array();
  for (int i = 0; i < 3; ++i) T.push_back({R_BS(i, 0), R_BS(i, 1), R_BS(i, 2), p_BS[i]});
  T.push_back({0, 0, 0, 1});
  const std::string file = tmp.write("vicon0.csv", Vicon0(rows, R_BS, p_BS));
  const auto full = FullStateComparisons(tmp, rows);
  const auto mapped = Comparisons(
      tmp, PoseGroundTruthPipeline(rows, {{"format", "euroc_pose"}, {"path", file}, {"T_BS", T}}),
      "mapped");
  const auto unmapped = Comparisons(
      tmp, PoseGroundTruthPipeline(rows, {{"format", "euroc_pose"}, {"path", file}}), "unmapped");
  ASSERT_EQ(mapped.size(), full.size());
  ASSERT_EQ(unmapped.size(), full.size());
  double worst = 0.0, unmapped_least = INFINITY;
  for (std::size_t k = 0; k < full.size(); ++k) {
    for (const char* key : {"position_error_m", "rotation_error_deg"}) {
      const double f = full[k].at(key), m = mapped[k].at(key);
      worst = std::max(worst, std::abs(m - f) / std::max(f, 1e-6));
    }
    unmapped_least = std::min(unmapped_least, unmapped[k].at("rotation_error_deg").get<double>());
  }
  EXPECT_LE(worst, 1e-9);
  // Without T_BS the sensor's rotation (about 135 degrees) is taken for the body's.
  EXPECT_GT(unmapped_least, 90.0);
  std::printf("errors through T_BS vs the full state: max relative difference %.1e\n", worst);
}

TEST(PoseGroundTruth, WhatAPoseCannotGiveIsRefusedAtItsPointer) {
  TempDir tmp;
  const auto rows = ReadFullGroundTruth();
  const std::string tum = tmp.write("gt.tum", Tum(rows));
  json p = PoseGroundTruthPipeline(rows, {{"format", "tum"}, {"path", tum}});
  p["tasks"][0]["bias"] = "ground_truth";
  p["tasks"][3]["start"] = {{"state", "ground_truth"}};
  const std::string path = tmp.write("p.json", p.dump());
  const CommandResult r =
      RunImuconv("run " + ShellQuote(path) + " -o " + ShellQuote(tmp.file("out.json")), tmp);
  EXPECT_EQ(r.exit_code, 2);  // a pipeline the data cannot serve; nothing written
  EXPECT_NE(r.err.find("/tasks/0/bias: the ground truth"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("format \"tum\") has poses only"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(tmp.file("out.json")));
  // A start state from it.
  p["tasks"][0].erase("bias");
  p["tasks"][0]["bias"] =
      PoseGroundTruthPipeline(rows, {{"format", "tum"}, {"path", tum}})["tasks"][0]["bias"];
  tmp.write("p.json", p.dump());
  const CommandResult r2 =
      RunImuconv("run " + ShellQuote(path) + " -o " + ShellQuote(tmp.file("out.json")), tmp);
  EXPECT_NE(r2.exit_code, 0);
  EXPECT_NE(r2.err.find("/tasks/3/start/state: the ground truth"), std::string::npos) << r2.err;
  EXPECT_FALSE(fs::exists(tmp.file("out.json")));
}

TEST(PoseGroundTruth, MalformedPoseFilesNameTheLine) {
  TempDir tmp;
  const auto rows = ReadFullGroundTruth();
  // Line 4 of the TUM file (the third row) made malformed in two ways.
  std::vector<std::string> lines;
  {
    std::stringstream ss(Tum(rows));
    for (std::string l; std::getline(ss, l);) lines.push_back(l);
  }
  auto with_line4 = [&](const std::string& l4) {
    std::string text;
    for (std::size_t i = 0; i < lines.size(); ++i) text += (i == 3 ? l4 : lines[i]) + "\n";
    return text;
  };
  const std::string stamp = lines[3].substr(0, lines[3].find(' '));
  struct Case {
    std::string name, text, expect;
  };
  const std::string short_row = with_line4(stamp + " 1 2 3 0 0 0");
  const std::string bad_quaternion = with_line4(stamp + " 1 2 3 0 0 0 2");
  const std::vector<Case> cases = {
      {"short.tum", short_row, ":4: expected 8 fields (TUM: t x y z qx qy qz qw)"},
      {"quat.tum", bad_quaternion, ":4: quaternion (qx, qy, qz, qw) has norm 2"},
  };
  for (const auto& c : cases) {
    const json p =
        PoseGroundTruthPipeline(rows, {{"format", "tum"}, {"path", tmp.write(c.name, c.text)}});
    const std::string path = tmp.write("p.json", p.dump());
    const CommandResult r =
        RunImuconv("run " + ShellQuote(path) + " -o " + ShellQuote(tmp.file("out.json")), tmp);
    EXPECT_NE(r.exit_code, 0) << c.name;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.name << ": " << r.err;
    EXPECT_FALSE(fs::exists(tmp.file("out.json")));
  }
}

TEST(PoseGroundTruth, ErrorsCsvLeavesTheVelocityColumnEmpty) {
  TempDir tmp;
  const auto rows = ReadFullGroundTruth();
  json p =
      PoseGroundTruthPipeline(rows, {{"format", "tum"}, {"path", tmp.write("gt.tum", Tum(rows))}});
  p["tasks"].erase(3);  // one propagate_by_preintegration task
  const std::string path = tmp.write("p.json", p.dump());
  const CommandResult r =
      RunImuconv("run " + ShellQuote(path) + " -o " + ShellQuote(tmp.file("out.json")) +
                     " --errors " + ShellQuote(tmp.file("errors.csv")),
                 tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::stringstream csv(ReadText(tmp.file("errors.csv")));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "k,t_end,t_end_abs_ns,position_error_m,rotation_error_deg,velocity_error_mps");
  int n = 0;
  while (std::getline(csv, line)) {
    ++n;
    EXPECT_EQ(line.back(), ',') << line;  // the velocity error is not known
  }
  EXPECT_EQ(n, 20);
}

}  // namespace
}  // namespace imuconv::test
