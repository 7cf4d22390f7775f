// imuconv optimize's two outputs, -o and --report, never share a file, however it is spelled
// (docs/outputs.md, "Two outputs are never one file"). Before the fix "r.html" and its absolute
// path, or "./r.html", were taken for different files while neither existed: exit 0, and the
// text table written last replaced the HTML report.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "../cli/euroc_slice.h"
#include "../cli/run_from.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

TEST(OptimizeDistinctOutputs, OneFileUnderTwoSpellingsIsRefusedBeforeAnyWork) {
  TempDir tmp;
  CopyEurocSlice(tmp);
  std::ofstream(tmp.file("noise.json")) << kEurocNoise.dump();
  const std::string inputs =
      "optimize --imu data/V1_01_easy_imu0_slice.csv --poses "
      "data/V1_01_easy_groundtruth_vicon2gt_slice.csv --noise noise.json --keyframe-step 1 ";
  const std::string abs = tmp.file("r.html");
  struct Case {
    std::string outputs, message;
  };
  const Case cases[] = {
      {"-o r.html --report " + ShellQuote(abs),
       "--report " + abs + " and -o r.html name the same file"},
      {"-o ./r.html --report r.html", "--report r.html and -o ./r.html name the same file"},
      {"-o r.html --report data/../r.html",
       "--report data/../r.html and -o r.html name the same file"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.outputs);
    const CommandResult r = RunImuconvFrom(tmp.path(), inputs + c.outputs, tmp);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(Has(r.err, c.message)) << r.err;
    EXPECT_FALSE(fs::exists(abs)) << "nothing is written when two outputs share a file";
    fs::remove(abs);  // each case starts without it
  }
}

}  // namespace
