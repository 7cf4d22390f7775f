// Two outputs of one command never share a file, however the file is spelled (docs/outputs.md,
// "Two outputs are never one file"): imuconv run's -o (or the pipeline's /output), --tum and
// --errors. Before the fix a bare relative name and "./" the same name, "sub/../x" and "x", or a
// link to a name not created yet were taken for different files: the run exited 0 and the last
// output written replaced the other (the JSON document lost under the TUM trajectory).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <string>

#include "euroc_slice.h"
#include "run_from.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

/// A directory holding the EuRoC slice and P.json: keyframes over the first 2 s and their
/// predictions (one propagate_by_preintegration task, so --tum and --errors need no
/// --trajectory-task).
struct TwoTasks {
  TempDir tmp;
  TwoTasks() {
    CopyEurocSlice(tmp);
    const json tasks = json::array({{{"type", "preintegrate"},
                                     {"name", "kf"},
                                     {"method", {{"propagator", "rk4"}}},
                                     {"conventions", {"gtsam_manifold"}},
                                     {"bias", "ground_truth"},
                                     {"keyframes", {{"start", 0.0}, {"end", 2.0}, {"step", 0.5}}}},
                                    {{"type", "propagate_by_preintegration"},
                                     {"name", "pred"},
                                     {"measurements", "kf"},
                                     {"state_convention", "left"},
                                     {"start", {{"state", "ground_truth"}}}}});
    tmp.write("P.json", EurocSlicePipeline(tasks).dump());
    fs::create_directories(tmp.file("sub"));
  }
  CommandResult run(const std::string& outputs) {
    return RunImuconvFrom(tmp.path(), "-q run P.json " + outputs, tmp);
  }
  /// The names in the directory besides data/, sub/ and P.json (outputs, temporaries).
  std::size_t written() const { return tmp.entries() - 3; }
  /// Removes them, so that each case starts from the same directory.
  void clear() const {
    for (const auto& e : fs::directory_iterator(tmp.path()))
      if (e.path().filename() != "data" && e.path().filename() != "sub" &&
          e.path().filename() != "P.json")
        fs::remove(e.path());
  }
};

TEST(DistinctOutputs, RunRefusesOneFileUnderTwoSpellings) {
  TwoTasks t;
  const std::string abs = t.tmp.file("out.json");
  struct Case {
    std::string outputs, message;
  };
  const Case cases[] = {
      {"-o ./out.json --tum out.json", "--tum out.json and -o ./out.json name the same file"},
      {"-o out.json --tum ./out.json", "--tum ./out.json and -o out.json name the same file"},
      {"-o out.json --errors sub/../out.json",
       "--errors sub/../out.json and -o out.json name the same file"},
      {"-o " + ShellQuote(abs) + " --tum out.json",
       "--tum out.json and -o " + abs + " name the same file"},
      {"-o out.json --tum t.tum --errors ./t.tum",
       "--errors ./t.tum and --tum t.tum name the same file"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.outputs);
    const CommandResult r = t.run(c.outputs);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(Has(r.err, c.message)) << r.err;
    EXPECT_EQ(t.written(), 0u) << "nothing is written when two outputs share a file";
    t.clear();
  }
  // The file both name is said once, links and dots resolved, as the kernel will find it.
  const CommandResult r = t.run("-o ./out.json --tum out.json");
  EXPECT_TRUE(Has(r.err, "(" + fs::canonical(t.tmp.path()).string() + "/out.json)")) << r.err;
}

TEST(DistinctOutputs, RunRefusesALinkToTheOtherOutputsNewName) {
  TwoTasks t;
  // link -> out.json, which does not exist yet: writing through the link creates out.json.
  ASSERT_EQ(::symlink("out.json", t.tmp.file("link").c_str()), 0);
  const CommandResult r = t.run("-o out.json --tum link");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "--tum link and -o out.json name the same file")) << r.err;
  EXPECT_FALSE(fs::exists(t.tmp.file("out.json")));
}

TEST(DistinctOutputs, RunRefusesTwoSpellingsOfAnExistingFileAndKeepsIt) {
  TwoTasks t;
  const std::string old = t.tmp.write("old.json", "kept\n");
  const CommandResult r = t.run("-o ./old.json --tum old.json");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "--tum old.json and -o ./old.json name the same file")) << r.err;
  EXPECT_EQ(ReadText(old), "kept\n");
}

TEST(DistinctOutputs, RunWritesOutputsOfTheSameNameInOtherDirectories) {
  // The check compares files, not names: one name in two directories is two files.
  TwoTasks t;
  const CommandResult r = t.run("-o out.json --tum sub/out.json --errors ./sub/../errors.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(json::parse(ReadText(t.tmp.file("out.json")))["tasks"].size(), 2u);
  // One TUM line per predicted interval (4 keyframe intervals over 2 s), one CSV line each and
  // the header.
  const std::string tum = ReadText(t.tmp.file("sub/out.json"));
  EXPECT_EQ(std::count(tum.begin(), tum.end(), '\n'), 4);
  const std::string csv = ReadText(t.tmp.file("errors.csv"));
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
}

}  // namespace
