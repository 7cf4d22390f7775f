// imuconv optimize through RunOptimizeCommand (no CLI11) on the bundled EuRoC V1_01 slice: the
// --json shape, -o, and every hostile input refused with exit 2, a message naming the culprit and
// nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "../cli/euroc_slice.h"
#include "../pipeline/pipeline_test_util.h"
#include "../support/imuconv_test.h"
#include "imuconv/cli/cmd_optimize.h"
#include "imuconv/cli/exit_codes.h"

namespace {

using namespace imuconv::test;
using imuconv::cli::CommandContext;
using imuconv::cli::OptimizeCommandOptions;
using nlohmann::json;

struct Output {
  int exit_code = -1;
  std::string out, err;
};

// Runs the command with std::cout and std::cerr redirected into strings (restored on any exit).
Output RunOptimize(const OptimizeCommandOptions& o) {
  unsetenv("IMUCONV_PLUGIN_PATH");  // the build tree's plugins only
  std::ostringstream out, err;
  struct Redirect {
    std::ostream& s;
    std::streambuf* old;
    Redirect(std::ostream& stream, std::streambuf* to) : s(stream), old(stream.rdbuf(to)) {}
    ~Redirect() { s.rdbuf(old); }
  } r_out(std::cout, out.rdbuf()), r_err(std::cerr, err.rdbuf());
  Output res;
  res.exit_code = imuconv::cli::RunOptimizeCommand(CommandContext{}, o);
  res.out = out.str();
  res.err = err.str();
  return res;
}

bool Has(const std::string& s, const std::string& sub) { return s.find(sub) != std::string::npos; }

// The slice's files copied into a temporary directory (a test that names an input as an output
// must not risk the repository's copy), a noise file beside them, and options for a 1 s step.
struct Slice {
  TempDir tmp;
  std::string imu, poses, noise;
  OptimizeCommandOptions o;
  Slice() {
    CopyEurocSlice(tmp);
    imu = tmp.file("data/V1_01_easy_imu0_slice.csv");
    poses = tmp.file("data/V1_01_easy_groundtruth_vicon2gt_slice.csv");
    noise = tmp.file("noise.json");
    std::ofstream(noise) << json{{"noise", kEurocNoise}}.dump();
    o.imu_path = imu;
    o.poses_path = poses;
    o.noise_path = noise;
    o.keyframe_step = 1.0;
    o.as_json = true;
  }
};

TEST(OptimizeCommand, JsonHasEveryKeyframeWithStateAndCovariance) {
  Slice s;
  const Output r = RunOptimize(s.o);
  ASSERT_EQ(r.exit_code, imuconv::cli::kExitOk) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["blocks"].size(), 5u);
  EXPECT_TRUE(j["solver"]["converged"].get<bool>());
  EXPECT_GT(j["solver"]["iterations"].get<int>(), 0);
  EXPECT_LE(j["solver"]["final_cost"].get<double>(), j["solver"]["initial_cost"].get<double>());
  EXPECT_FALSE(j["solver"]["rounds"].empty());
  const json& kfs = j["keyframes"];
  ASSERT_GE(kfs.size(), 2u);
  double t_prev = -1e9;
  for (const json& k : kfs) {
    if (&k != &kfs.front()) {  // keyframes every step; 1e-9 s the rounding of relative times
      EXPECT_NEAR(k["t"].get<double>() - t_prev, 1.0, 1e-9);
    }
    t_prev = k["t"].get<double>();
    for (const char* key : {"p", "v", "bg", "ba", "reference_bg", "reference_ba"})
      EXPECT_EQ(k[key].size(), 3u) << key;
    ASSERT_EQ(k["q_wxyz"].size(), 4u);
    double qn = 0;
    for (const json& c : k["q_wxyz"]) qn += c.get<double>() * c.get<double>();
    EXPECT_NEAR(qn, 1.0, 1e-12);  // unit to rounding: the output normalises it
    EXPECT_GE(k["q_wxyz"][0].get<double>(), 0.0);
    ASSERT_EQ(k["cov"].size(), 15u);
    for (int a = 0; a < 15; ++a) {
      ASSERT_EQ(k["cov"][a].size(), 15u);
      EXPECT_GT(k["cov"][a][a].get<double>(), 0.0);
      for (int b = 0; b < a; ++b)  // a covariance: symmetric, to its rounding
        EXPECT_NEAR(k["cov"][a][b].get<double>(), k["cov"][b][a].get<double>(),
                    1e-12 * std::sqrt(k["cov"][a][a].get<double>() * k["cov"][b][b].get<double>()));
    }
  }
  EXPECT_TRUE(j.contains("bias_vs_reference"));
}

TEST(OptimizeCommand, OutputFileTakesTheDocumentAndStdoutStaysEmpty) {
  Slice s;
  s.o.output_path = s.tmp.file("out.json");
  const Output r = RunOptimize(s.o);
  ASSERT_EQ(r.exit_code, imuconv::cli::kExitOk) << r.err;
  EXPECT_TRUE(r.out.empty());
  const json j = json::parse(ReadText(s.o.output_path));
  EXPECT_FALSE(j["keyframes"].empty());
}

TEST(OptimizeCommand, ReportDrawsEachBiasAgainstTheGroundTruth) {
  Slice s;
  s.o.report_path = s.tmp.file("report.html");
  const Output r = RunOptimize(s.o);
  ASSERT_EQ(r.exit_code, imuconv::cli::kExitOk) << r.err;
  const std::string page = ReadText(s.o.report_path);
  for (const char* axis : {"bg.x", "bg.y", "bg.z", "ba.x", "ba.y", "ba.z"})
    EXPECT_TRUE(Has(page, std::string(axis) + ": the estimate; the ground truth")) << axis;
  EXPECT_TRUE(Has(page, "<svg"));
  EXPECT_TRUE(Has(page, "estimate \u00b13 sigma"));
}

// The slice's poses rewritten as a TUM trajectory and as EuRoC vicon0 rows (every digit kept):
// the same poses, so the same estimate (to rounding); only the reference biases are gone, and
// vicon0 warns
// that its poses are the marker's.
TEST(OptimizeCommand, TumAndVicon0PosesGiveTheSameEstimate) {
  Slice s;
  const Output euroc = RunOptimize(s.o);
  ASSERT_EQ(euroc.exit_code, imuconv::cli::kExitOk) << euroc.err;
  const json ref = json::parse(euroc.out);
  std::ifstream in(s.poses);
  std::ofstream tum(s.tmp.file("poses.tum")), vicon(s.tmp.file("vicon0.csv"));
  vicon << "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],"
           "q_RS_z []\n";
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
    ASSERT_EQ(f.size(), 17u);
    // TUM: seconds with the nanoseconds' digits, then p and q as x y z w.
    const std::string ns = f[0];
    tum << ns.substr(0, ns.size() - 9) << "." << ns.substr(ns.size() - 9) << " " << f[1] << " "
        << f[2] << " " << f[3] << " " << f[5] << " " << f[6] << " " << f[7] << " " << f[4] << "\n";
    vicon << f[0] << "," << f[1] << "," << f[2] << "," << f[3] << "," << f[4] << "," << f[5] << ","
          << f[6] << "," << f[7] << "\n";
  }
  tum.close();
  vicon.close();
  for (const std::string& file : {s.tmp.file("poses.tum"), s.tmp.file("vicon0.csv")}) {
    s.o.poses_path = file;
    const Output r = RunOptimize(s.o);
    ASSERT_EQ(r.exit_code, imuconv::cli::kExitOk) << file << "\n" << r.err;
    const json j = json::parse(r.out);
    EXPECT_FALSE(j.contains("bias_vs_reference")) << file;
    ASSERT_EQ(j["keyframes"].size(), ref["keyframes"].size()) << file;
    // Not to the bit: the TUM reader's decimal seconds and each reader's quaternion
    // normalisation round differently (1e-16), which the solve carries at that scale; 1e-9 is
    // that and far below any difference of poses (the slice's noise is 1e-4 and more).
    for (std::size_t k = 0; k < ref["keyframes"].size(); ++k) {
      EXPECT_NEAR(j["keyframes"][k]["t"].get<double>(), ref["keyframes"][k]["t"].get<double>(),
                  1e-9);
      for (const char* key : {"p", "q_wxyz", "v", "bg", "ba"})
        for (std::size_t a = 0; a < ref["keyframes"][k][key].size(); ++a)
          EXPECT_NEAR(j["keyframes"][k][key][a].get<double>(),
                      ref["keyframes"][k][key][a].get<double>(), 1e-9)
              << file << " keyframe " << k << " " << key;
    }
    EXPECT_EQ(Has(r.err, "vicon0 poses are the Vicon marker's"), file == s.tmp.file("vicon0.csv"))
        << r.err;
  }
}

// A solve stopped before it converged is an answer of its own: exit 1, converged false, no
// covariances, and a warning, never numbers passed off as an optimum.
TEST(OptimizeCommand, ASolveThatDidNotConvergeSaysSo) {
  Slice s;
  s.o.max_iterations =
      1;  // the first solve starts at cost ~1e6 (zero biases): one step is not enough
  const Output r = RunOptimize(s.o);
  EXPECT_EQ(r.exit_code, imuconv::cli::kExitInconsistent) << r.err;
  const json j = json::parse(r.out);
  EXPECT_FALSE(j["solver"]["converged"].get<bool>());
  EXPECT_EQ(j["solver"]["termination"], "NO_CONVERGENCE");
  EXPECT_FALSE(j["covariance"]["computed"].get<bool>());
  EXPECT_TRUE(j["keyframes"][0]["cov"].is_null());
  EXPECT_TRUE(Has(r.err, "the solve did not converge")) << r.err;
}

// Kalibr's imu.yaml with EuRoC's densities (tests/data/kalibr) is the JSON noise object.
TEST(OptimizeCommand, KalibrNoiseIsTheJsonNoise) {
  Slice s;
  const Output json_noise = RunOptimize(s.o);
  s.o.noise_path = DataPath("kalibr/euroc_imu.yaml");
  const Output kalibr = RunOptimize(s.o);
  ASSERT_EQ(kalibr.exit_code, imuconv::cli::kExitOk) << kalibr.err;
  EXPECT_EQ(json::parse(kalibr.out)["keyframes"], json::parse(json_noise.out)["keyframes"]);
}

// Each case: what is wrong, and what the message must name.
void ExpectRefused(const OptimizeCommandOptions& o, const std::string& named) {
  const Output r = RunOptimize(o);
  EXPECT_EQ(r.exit_code, imuconv::cli::kExitBadInput) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_TRUE(Has(r.err, named)) << r.err;
}

TEST(OptimizeCommand, MissingInputFilesAreNamed) {
  Slice s;
  s.o.imu_path = s.tmp.file("absent_imu.csv");
  ExpectRefused(s.o, "absent_imu.csv");
  Slice t;
  t.o.poses_path = t.tmp.file("absent_poses.csv");
  ExpectRefused(t.o, "absent_poses.csv");
  Slice u;
  u.o.noise_path = u.tmp.file("absent_noise.json");
  ExpectRefused(u.o, "absent_noise.json");
}

// Without --pipeline there is no /noise to fall back on: the call is refused as a usage error
// before any file is read (an absent IMU file is not what it reports).
TEST(OptimizeCommand, NoNoiseAndNoPipelineIsAUsageErrorBeforeAnyFileIsRead) {
  Slice s;
  s.o.noise_path.clear();
  s.o.imu_path = s.tmp.file("absent_imu.csv");
  try {
    (void)RunOptimize(s.o);
    ADD_FAILURE() << "no UsageError";
  } catch (const imuconv::cli::UsageError& e) {
    EXPECT_TRUE(Has(e.message, "give --noise")) << e.message;
  }
}

TEST(OptimizeCommand, BadPoseColumnsNameTheFileAndLine) {
  Slice s;
  std::ofstream(s.poses) << "#time(ns),px,py,pz,qw,qx\n1403715293262142976,1,2,3,1,0\n";
  ExpectRefused(s.o, "V1_01_easy_groundtruth_vicon2gt_slice.csv:2");
}

TEST(OptimizeCommand, KeyframeStepOutsideTheDataIsRefused) {
  Slice s;
  s.o.keyframe_step = 1000.0;  // the slice is 20 s
  ExpectRefused(s.o, "is longer than");
  s.o.keyframe_step = 0.001;  // EuRoC's IMU is 200 Hz: 0.005 s
  ExpectRefused(s.o, "shorter than the IMU's sample period");
  s.o.keyframe_step = -1.0;
  ExpectRefused(s.o, "--keyframe-step");
}

TEST(OptimizeCommand, PosesThatMissTheImuDataAreRefused) {
  Slice s;
  // Two poses 10^6 s after the slice (whose 20 s start at the IMU's first stamp, 1403715293...).
  std::ofstream(s.poses) << "#time(ns),px,py,pz,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz\n"
                            "1404715293262142976,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n"
                            "1404715293312142976,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n";
  ExpectRefused(s.o, "do not overlap");
}

TEST(OptimizeCommand, UnknownMethodAndConventionAreNamed) {
  Slice s;
  s.o.method = "rk5";
  ExpectRefused(s.o, "--method: unknown propagator or preintegrator rk5");
  Slice t;
  t.o.convention = "lefty";
  ExpectRefused(t.o, "--convention");
}

TEST(OptimizeCommand, AnOutputNamingAnInputIsRefusedAndTheInputKept) {
  Slice s;
  const std::string before = ReadText(s.imu);
  s.o.output_path = s.imu;
  // OutputFile's own words, whichever of its checks sees it first (this process's inputs, or
  // the command's list of them).
  ExpectRefused(s.o, "is the same file as");
  EXPECT_EQ(ReadText(s.imu), before);
  Slice o;
  o.o.output_path = o.tmp.file("same.html");
  o.o.report_path = o.tmp.file("same.html");
  ExpectRefused(o.o, "--report " + o.tmp.file("same.html") + " and -o " + o.tmp.file("same.html") +
                         " name the same file");
  Slice t;
  const std::string poses_before = ReadText(t.poses);
  t.o.report_path = t.poses;
  ExpectRefused(t.o, "is the same file as");
  EXPECT_EQ(ReadText(t.poses), poses_before);
}

}  // namespace
