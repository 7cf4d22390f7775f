// The pipeline task "optimize" (`imuconv run`) against `imuconv optimize --pipeline` on the same
// pipeline: one computation, the same numbers; and its grammar's refusals, each at its pointer.
#include <gtest/gtest.h>

#include <fstream>

#include "../cli/euroc_slice.h"
#include "../pipeline/pipeline_test_util.h"

namespace {

using namespace imuconv::test;
using nlohmann::json;

std::string WritePipeline(const TempDir& tmp, const json& tasks) {
  CopyEurocSlice(tmp);
  const std::string path = tmp.file("p.json");
  std::ofstream(path) << EurocSlicePipeline(tasks).dump(1);
  return path;
}

TEST(OptimizeTask, WritesWhatTheCommandPrints) {
  TempDir tmp;
  const std::string p = WritePipeline(
      tmp, json::array({{{"type", "optimize"}, {"name", "opt"}, {"keyframe_step", 2.0}}}));
  const CommandResult run = RunImuconv("run " + ShellQuote(p), tmp);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json out = json::parse(run.out);
  const json& task = TaskOutput(out, "opt");
  EXPECT_EQ(task["type"], "optimize");
  const json cli =
      RunImuconvJson("optimize", "--pipeline " + ShellQuote(p) + " --keyframe-step 2.0", tmp);
  ASSERT_FALSE(cli.is_null());
  // The same solve on the same data: every number equal (both print doubles that read back
  // exactly), but the solver's own timings.
  ASSERT_EQ(task["keyframes"].size(), cli["keyframes"].size());
  EXPECT_EQ(task["keyframes"], cli["keyframes"]);
  EXPECT_EQ(task["solver"]["iterations"], cli["solver"]["iterations"]);
  EXPECT_EQ(task["solver"]["final_cost"], cli["solver"]["final_cost"]);
}

TEST(OptimizeTask, ASolveThatDidNotConvergeSaysSoInTheDocument) {
  TempDir tmp;
  const std::string p = WritePipeline(tmp, json::array({{{"type", "optimize"},
                                                         {"name", "opt"},
                                                         {"keyframe_step", 2.0},
                                                         {"max_iterations", 1}}}));
  const CommandResult run = RunImuconv("run " + ShellQuote(p), tmp);
  // The document is written whole, and the run exits 1 (docs/exit-codes.md), as imuconv
  // optimize does for the same solve: no answer is given as if it were one.
  ASSERT_EQ(run.exit_code, 1) << run.err;
  const json out = json::parse(run.out);
  const json& task = TaskOutput(out, "opt");
  EXPECT_FALSE(task["solver"]["converged"].get<bool>());
  EXPECT_FALSE(task["covariance"]["computed"].get<bool>());
  EXPECT_NE(run.err.find("DID NOT CONVERGE"), std::string::npos) << run.err;
  // Quiet, the summary is gone but the exit code and the one line on stderr stay.
  const CommandResult quiet = RunImuconv("-q run " + ShellQuote(p), tmp);
  EXPECT_EQ(quiet.exit_code, 1) << quiet.err;
  EXPECT_NE(quiet.err.find("optimize task 'opt': the solve did not converge"), std::string::npos)
      << quiet.err;
}

TEST(OptimizeTask, RefusesWhatItCannotUseAtItsPointer) {
  TempDir tmp;
  const std::string p = WritePipeline(tmp, json::array({{{"type", "optimize"},
                                                         {"name", "opt"},
                                                         {"keyframe_step", -1.0},
                                                         {"pose_sigma", {0.01}},
                                                         {"method", "rk5"}}}));
  const CommandResult r = RunImuconv("run " + ShellQuote(p), tmp);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(r.out.empty());
  for (const char* ptr : {"/tasks/0/keyframe_step", "/tasks/0/pose_sigma"})
    EXPECT_NE(r.err.find(ptr), std::string::npos) << ptr << "\n" << r.err;

  // Plugin ids are checked once the document parses (the stage "check ids").
  std::ofstream(tmp.file("m.json")) << EurocSlicePipeline(json::array({{{"type", "optimize"},
                                                                        {"name", "opt"},
                                                                        {"keyframe_step", 1.0},
                                                                        {"method", "rk5"}}}))
                                           .dump(1);
  const CommandResult m = RunImuconv("run " + ShellQuote(tmp.file("m.json")), tmp);
  EXPECT_EQ(m.exit_code, 2) << m.err;
  EXPECT_NE(m.err.find("/tasks/0/method"), std::string::npos) << m.err;

  json no_gt = EurocSlicePipeline(
      json::array({{{"type", "optimize"}, {"name", "opt"}, {"keyframe_step", 1.0}}}));
  no_gt.erase("ground_truth");
  std::ofstream(tmp.file("q.json")) << no_gt.dump(1);
  const CommandResult q = RunImuconv("run " + ShellQuote(tmp.file("q.json")), tmp);
  EXPECT_EQ(q.exit_code, 2) << q.err;
  EXPECT_NE(q.err.find("/tasks/0/type"), std::string::npos) << q.err;
  EXPECT_NE(q.err.find("/ground_truth"), std::string::npos) << q.err;
}

}  // namespace
