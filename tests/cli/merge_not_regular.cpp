// imuconv merge given a shard that is not a regular file: refused at once, naming it, as every
// input is (docs/outputs.md; README: a FIFO never hangs), whichever place it has among the
// shards. Before the fix merge read each argument's first bytes with a blocking std::ifstream
// to tell a montecarlo shard apart, and waited for ever on a FIFO with no writer.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <string>

#include "euroc_slice.h"
#include "run_from.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

TEST(MergeNotRegular, FifoOrDeviceOrDirectoryIsRefusedWithoutWaiting) {
  TempDir tmp;
  CopyEurocSlice(tmp);
  const json tasks = json::array({{{"type", "preintegrate"},
                                   {"name", "kf_a"},
                                   {"method", {{"propagator", "rk4"}}},
                                   {"bias", "ground_truth"},
                                   {"keyframes", {{"start", 0.0}, {"end", 1.0}, {"step", 0.5}}}},
                                  {{"type", "preintegrate"},
                                   {"name", "kf_b"},
                                   {"method", {{"propagator", "rk4"}}},
                                   {"bias", "ground_truth"},
                                   {"keyframes", {{"start", 1.0}, {"end", 2.0}, {"step", 0.5}}}}});
  tmp.write("P.json", EurocSlicePipeline(tasks).dump());
  const CommandResult shard =
      RunImuconvFrom(tmp.path(), "-q run P.json --shard 0/2 -o s0.json", tmp);
  ASSERT_EQ(shard.exit_code, 0) << shard.err;
  ASSERT_EQ(::mkfifo(tmp.file("ff").c_str(), 0600), 0);
  struct Case {
    std::string shards, message;
  };
  const Case cases[] = {
      {"s0.json ff", "ff: is a FIFO, not a regular file"},
      {"ff s0.json", "ff: is a FIFO, not a regular file"},
      {"s0.json /dev/null", "/dev/null: is a character device, not a regular file"},
      {"s0.json data", "data: is a directory, not a file"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.shards);
    const CommandResult r = RunImuconvFrom(tmp.path(), "merge -o m.json " + c.shards, tmp);
    EXPECT_NE(r.exit_code, kTimedOut) << "merge waited on the FIFO";
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(Has(r.err, "merge: " + c.message)) << r.err;
    EXPECT_FALSE(fs::exists(tmp.file("m.json")));
  }
}

}  // namespace
