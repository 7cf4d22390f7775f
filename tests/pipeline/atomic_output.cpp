// Output files are written atomically: a temporary in the same directory, renamed over the
// target. A failing run leaves no output (and an existing file untouched), and no temporaries.
#include <gtest/gtest.h>

#include "imuconv/pipeline/json_io.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv::test;
using imuconv::pipeline::WriteFileAtomically;

TEST(AtomicWrite, WritesReplacesAndLeavesNoTemporaries) {
  TempDir tmp;
  const std::string f = tmp.file("out.json");
  WriteFileAtomically(f, "{\"a\": 1}\n");
  EXPECT_EQ(ReadText(f), "{\"a\": 1}\n");
  WriteFileAtomically(f, "{\"a\": 2}\n");
  EXPECT_EQ(ReadText(f), "{\"a\": 2}\n");
  EXPECT_EQ(tmp.entries(), 1u);
}

TEST(AtomicWrite, MissingDirectoryThrowsAndWritesNothing) {
  TempDir tmp;
  const std::string f = tmp.file("no/such/dir/out.json");
  const std::string msg = MessageOf<imuconv::Error>([&] { WriteFileAtomically(f, "x"); });
  EXPECT_NE(msg.find(f + ": cannot create a temporary file in"), std::string::npos) << msg;
  EXPECT_EQ(tmp.entries(), 0u);
}

TEST(AtomicWrite, FailingRunsLeaveNoOutput) {
  TempDir tmp;
  // A valid pipeline next to a broken one (interval outside the data: found only after the
  // data is read) and one whose IMU file is missing.
  nlohmann::json doc = nlohmann::json::parse(ReadText(SourcePath("examples/inline_basics.json")));
  const std::string ok = tmp.write("ok.json", doc.dump());
  ASSERT_EQ(doc["tasks"][0]["name"], "direct");
  doc["tasks"][0]["interval"]["t_end"] = 9.0;
  const std::string late = tmp.write("late.json", doc.dump());

  // 1. A new output file is not created.
  const std::string out = tmp.file("result.json");
  CommandResult r = RunImuconv("run " + ShellQuote(late) + " -o " + ShellQuote(out), tmp);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(late + ": /tasks/0/interval/t_end: t = 9 s is after the last IMU sample"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));

  // 2. An existing output file is left as it was.
  std::ofstream(out) << "previous result\n";
  r = RunImuconv("run " + ShellQuote(late) + " -o " + ShellQuote(out), tmp);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(ReadText(out), "previous result\n");

  // 3. A good run replaces it; no temporaries are left behind in either case.
  r = RunImuconv("run " + ShellQuote(ok) + " -o " + ShellQuote(out) + " --quiet", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(ReadText(out))["tasks"].size(), 10u);
  EXPECT_EQ(tmp.entries(), 3u);  // ok.json, late.json, result.json

  // 4. An output directory that does not exist: an error, nothing written.
  const std::string nowhere = tmp.file("missing/result.json");
  r = RunImuconv("run " + ShellQuote(ok) + " -o " + ShellQuote(nowhere) + " --quiet", tmp);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(nowhere + ": cannot create a temporary file"), std::string::npos) << r.err;
  EXPECT_EQ(tmp.entries(), 3u);
}

}  // namespace
