// The global -q and -v flags: -q leaves only results, warnings and errors; -v adds the plugin
// search path, the plugins loaded and the time taken, on stderr, and changes no result.
#include <gtest/gtest.h>

#include <string>

#include "../pipeline/pipeline_test_util.h"

namespace imuconv::test {
namespace {

const std::string kExample = SourcePath("examples/inline_basics.json");

TEST(Verbosity, QuietLeavesOnlyTheResult) {
  TempDir tmp;
  const std::string out = tmp.file("out.json");
  const CommandResult normal =
      RunImuconv("run " + ShellQuote(kExample) + " -o " + ShellQuote(out), tmp);
  ASSERT_EQ(normal.exit_code, 0) << normal.err;
  EXPECT_NE(normal.out.find("wrote"), std::string::npos);  // the summary and the "wrote" line
  const std::string first = ReadText(out);
  const CommandResult quiet =
      RunImuconv("-q run " + ShellQuote(kExample) + " -o " + ShellQuote(out), tmp);
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.out, "");
  EXPECT_EQ(quiet.err, "");
  EXPECT_EQ(ReadText(out), first);
  // Results are still printed: -q plugins --json is the list.
  const CommandResult list = RunImuconv("-q plugins --json", tmp);
  ASSERT_EQ(list.exit_code, 0);
  EXPECT_NE(list.out.find("\"euler\""), std::string::npos);
}

TEST(Verbosity, VerboseAddsTheSearchPathPluginsAndTimeOnStderr) {
  TempDir tmp;
  const CommandResult plain = RunImuconv("plugins --json", tmp);
  const CommandResult verbose = RunImuconv("-v plugins --json", tmp);
  ASSERT_EQ(verbose.exit_code, 0) << verbose.err;
  EXPECT_EQ(verbose.out, plain.out);  // the result is the same
  EXPECT_NE(verbose.err.find("imuconv: plugin search path: "), std::string::npos) << verbose.err;
  EXPECT_NE(verbose.err.find("imuconv: loaded propagator euler 1.0.0 from "), std::string::npos)
      << verbose.err;
  EXPECT_NE(verbose.err.find("imuconv: plugins took "), std::string::npos) << verbose.err;
  const std::string out = tmp.file("out.json");
  const CommandResult run =
      RunImuconv("-v run " + ShellQuote(kExample) + " -o " + ShellQuote(out), tmp);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("imuconv: plugin search path: "), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("imuconv: run took "), std::string::npos) << run.err;
}

TEST(Verbosity, QuietAndVerboseTogetherAreAUsageError) {
  TempDir tmp;
  const CommandResult r = RunImuconv("-q -v plugins", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("excludes"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace imuconv::test
