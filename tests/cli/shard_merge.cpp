// imuconv run --shard K/N and imuconv merge: the N shards of a pipeline with several tasks, merged,
// are the bytes of one whole run (for N = 1, 2, 3, the shards given in any order and run on a
// different thread count than the whole run); the split follows the documented rule (units
// that no reference crosses, contiguous blocks of units); a hostile merge (a shard missing,
// given twice, from another pipeline or other data, of another split, truncated, not a shard)
// exits 2 naming the file and leaves no output and no temporary.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "euroc_slice.h"
#include "shard_forgery.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

/// A pipeline over the bundled 20 s EuRoC slice with eight tasks in four units:
/// {kf_a, pred_a}, {kf_b, pred_b}, {kf_c}, {kf_d, kf_e, pred_d} (pred_d names kf_d across kf_e,
/// so the three stay together).
json BatchPipeline(double gravity_z = -9.81) {
  const auto preintegrate = [](const std::string& name, const json& method, double a, double b) {
    return json{{"type", "preintegrate"}, {"name", name},
                {"method", method},       {"conventions", {"gtsam_manifold"}},
                {"bias", "ground_truth"}, {"keyframes", {{"start", a}, {"end", b}, {"step", 0.1}}}};
  };
  const auto predict = [](const std::string& name, const std::string& of,
                          const std::string& chart) {
    return json{{"type", "propagate_by_preintegration"},
                {"name", name},
                {"measurements", of},
                {"state_convention", chart},
                {"start", {{"state", "ground_truth"}}}};
  };
  const json rk4 = {{"propagator", "rk4"}}, manifold = {{"preintegrator", "manifold"}};
  return EurocSlicePipeline(
      json::array(
          {preintegrate("kf_a", rk4, 0.0, 6.0), predict("pred_a", "kf_a", "left"),
           preintegrate("kf_b", manifold, 6.0, 12.0), predict("pred_b", "kf_b", "gtsam_navstate"),
           preintegrate("kf_c", rk4, 12.0, 15.0), preintegrate("kf_d", manifold, 15.0, 20.0),
           preintegrate("kf_e", rk4, 2.0, 4.0), predict("pred_d", "kf_d", "left")}),
      gravity_z);
}

/// A temporary directory holding the slice data and the batch pipeline (P.json).
struct Batch {
  TempDir tmp;
  std::string pipeline;
  Batch() {
    CopyEurocSlice(tmp);
    pipeline = tmp.write("P.json", BatchPipeline().dump(2));
  }
  /// Runs shard k of n into S<k>of<n>.json (or the whole run into whole.json) and returns the path.
  std::string run(const std::string& extra, const std::string& out, unsigned threads) {
    const CommandResult r =
        RunImuconv("-q run " + ShellQuote(pipeline) + " " + extra + " -j " +
                       std::to_string(threads) + " -o " + ShellQuote(tmp.file(out)),
                   tmp);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return tmp.file(out);
  }
  std::string shard(unsigned k, unsigned n) {
    return run("--shard " + std::to_string(k) + "/" + std::to_string(n),
               "S" + std::to_string(k) + "of" + std::to_string(n) + ".json", 2);
  }
  CommandResult merge(const std::string& out, const std::vector<std::string>& shards) {
    std::string args = "merge -o " + ShellQuote(tmp.file(out));
    for (const auto& s : shards) args += " " + ShellQuote(s);
    return RunImuconv(args, tmp);
  }
};

TEST(ShardMerge, ShardsMergeToTheWholeRunsBytes) {
  Batch b;
  // The whole run serially, the shards on two threads: the document depends on neither.
  const std::string whole = ReadText(b.run("", "whole.json", 1));
  const json doc = json::parse(whole);
  ASSERT_EQ(doc["tasks"].size(), 8u);
  ASSERT_FALSE(doc.contains("shard"));
  // The documented split (RunOptions::Shard): units {0,1} {2,3} {4} {5,6,7}; shard k of n
  // takes units [k*4/n, (k+1)*4/n).
  const std::vector<std::vector<std::pair<int, int>>> expected_blocks = {
      {{0, 8}}, {{0, 4}, {4, 8}}, {{0, 2}, {2, 4}, {4, 8}}};
  for (unsigned n = 1; n <= 3; ++n) {
    SCOPED_TRACE("n = " + std::to_string(n));
    std::vector<std::string> shards;
    for (unsigned k = 0; k < n; ++k) {
      shards.push_back(b.shard(k, n));
      const json s = json::parse(ReadText(shards.back()));
      const auto [first, end] = expected_blocks[n - 1][k];
      EXPECT_EQ(s["shard"]["index"], k);
      EXPECT_EQ(s["shard"]["count"], n);
      EXPECT_EQ(s["shard"]["tasks"], 8);
      EXPECT_EQ(s["shard"]["first_task"], first);
      EXPECT_EQ(s["shard"]["end_task"], end);
      ASSERT_EQ(s["tasks"].size(), static_cast<std::size_t>(end - first));
      // The shard's tasks are the whole run's, value for value.
      for (int i = first; i < end; ++i)
        EXPECT_EQ(s["tasks"][i - first], doc["tasks"][i]) << "task " << i;
      // Its head is the whole run's.
      for (const auto& [key, value] : doc.items()) {
        if (key == "tasks") continue;
        EXPECT_EQ(s[key], value) << key;
      }
    }
    // Given in reverse order: the merge orders them by their index.
    std::vector<std::string> reversed(shards.rbegin(), shards.rend());
    const CommandResult r = b.merge("merged.json", reversed);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // Byte identity, the claim of imuconv merge: no tolerance.
    EXPECT_EQ(ReadText(b.tmp.file("merged.json")), whole);
    fs::remove(b.tmp.file("merged.json"));
  }
}

TEST(ShardMerge, MoreShardsThanUnitsLeavesSomeEmpty) {
  Batch b;
  const std::string whole = ReadText(b.run("", "whole.json", 2));
  std::vector<std::string> shards;
  for (unsigned k = 0; k < 6; ++k) shards.push_back(b.shard(k, 6));
  // Six shards over four units: k*4/6 = 0,0,1,2,2,3 -> shards 0 and 3 are empty.
  EXPECT_TRUE(json::parse(ReadText(shards[0]))["tasks"].empty());
  EXPECT_TRUE(json::parse(ReadText(shards[3]))["tasks"].empty());
  const CommandResult r = b.merge("merged.json", shards);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(ReadText(b.tmp.file("merged.json")), whole);
}

/// A merge that must fail: exit 2, the message names `file` and says `why`, and the directory
/// holds no output and nothing new (no temporary).
void ExpectMergeRefused(Batch& b, const std::vector<std::string>& shards, const std::string& file,
                        const std::string& why) {
  const std::size_t before = b.tmp.entries();
  const CommandResult r = b.merge("out.json", shards);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, file)) << r.err;
  EXPECT_TRUE(Has(r.err, why)) << r.err;
  EXPECT_FALSE(fs::exists(b.tmp.file("out.json")));
  EXPECT_EQ(b.tmp.entries(), before);
}

TEST(ShardMerge, HostileMergesAreRefused) {
  Batch b;
  const std::string s0 = b.shard(0, 3), s1 = b.shard(1, 3), s2 = b.shard(2, 3);
  {
    SCOPED_TRACE("missing");
    const CommandResult r = b.merge("out.json", {s0, s2});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(Has(r.err, "missing 1 of the 3 shards (index 1)")) << r.err;
    EXPECT_FALSE(fs::exists(b.tmp.file("out.json")));
  }
  {
    SCOPED_TRACE("duplicated");
    ExpectMergeRefused(b, {s0, s1, s2, s1}, "S1of3.json", "shard 1 of 3 is given twice");
  }
  {
    SCOPED_TRACE("another split");
    const std::string other = b.shard(0, 2);
    ExpectMergeRefused(b, {other, s1, s2}, "S1of3.json", "one is shard 1 of 3, the other of 2");
  }
  {
    SCOPED_TRACE("another pipeline");
    // Same tasks, same task count, another gravity: the heads differ.
    const std::string q = b.tmp.write("Q.json", BatchPipeline(-9.80665).dump(2));
    const CommandResult r = RunImuconv(
        "-q run " + ShellQuote(q) + " --shard 1/3 -o " + ShellQuote(b.tmp.file("Q1of3.json")),
        b.tmp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ExpectMergeRefused(b, {s0, b.tmp.file("Q1of3.json"), s2}, "Q1of3.json",
                       "not shards of one run");
  }
  {
    SCOPED_TRACE("other data under the same name");
    const std::string imu = b.tmp.file("data/V1_01_easy_imu0_slice.csv");
    const std::string original = ReadText(imu);
    // One digit of the last sample's last column changed: same size and rows, other bytes.
    std::string changed = original;
    const std::size_t last_digit = changed.find_last_of("0123456789");
    changed[last_digit] = changed[last_digit] == '1' ? '2' : '1';
    b.tmp.write("data/V1_01_easy_imu0_slice.csv", changed);
    const std::string moved = b.run("--shard 1/3", "D1of3.json", 2);
    b.tmp.write("data/V1_01_easy_imu0_slice.csv", original);
    ExpectMergeRefused(b, {s0, moved, s2}, "D1of3.json", "/shard/inputs");
  }
  {
    SCOPED_TRACE("another CPU's kernel instance");
    // As a shard from a node whose CPU runs another SIMD instance (FMA or not) would say.
    std::string text = ReadText(s1);
    const std::string key = "\"kernel_instance\": \"";
    const std::size_t at = text.find(key);
    ASSERT_NE(at, std::string::npos);
    const std::size_t name = at + key.size(), name_end = text.find('"', name);
    const std::string here = text.substr(name, name_end - name);
    text.replace(name, here.size(), here == "baseline" ? "avx2" : "baseline");
    // Resealed: such a shard's own hash is right (an edit that is not is shard_integrity.cpp's).
    const std::string edited = b.tmp.write("K1of3.json", ResealRunShard(text));
    ExpectMergeRefused(b, {s0, edited, s2}, "K1of3.json",
                       "different SIMD instances of the kernels (/shard/kernel_instance");
  }
  {
    SCOPED_TRACE("another imuconv version");
    // The same inputs, a head that differs (as a shard written by another build would):
    // the version string edited in a copy of shard 1.
    std::string text = ReadText(s1);
    const std::string key = "\"imuconv_version\": \"";
    const std::size_t at = text.find(key);
    ASSERT_NE(at, std::string::npos);
    text.insert(at + key.size(), "9.9-");
    const std::string edited = b.tmp.write("V1of3.json", ResealRunShard(text));
    ExpectMergeRefused(b, {s0, edited, s2}, "V1of3.json", "differ before \"tasks\" at line 2");
  }
  {
    SCOPED_TRACE("truncated");
    const std::string text = ReadText(s1);
    const std::string half = b.tmp.write("half.json", text.substr(0, text.size() / 2));
    ExpectMergeRefused(b, {s0, half, s2}, "half.json", "truncated shard");
    // Cut by its last byte (the closing newline) only.
    const std::string cut = b.tmp.write("cut.json", text.substr(0, text.size() - 1));
    ExpectMergeRefused(b, {s0, cut, s2}, "cut.json", "truncated shard");
  }
  {
    SCOPED_TRACE("not a shard");
    const std::string whole = b.run("", "whole.json", 2);
    ExpectMergeRefused(b, {whole}, "whole.json", "not a shard");
  }
  {
    SCOPED_TRACE("text after the document");
    const std::string longer = b.tmp.write("longer.json", ReadText(s2) + "{}");
    ExpectMergeRefused(b, {s0, s1, longer}, "longer.json", "more text after the end");
  }
  // The output is never one of the shards: refused, the shard unchanged.
  const std::string before = ReadText(s0);
  const CommandResult r = RunImuconv("merge -o " + ShellQuote(s0) + " " + ShellQuote(s0) + " " +
                                         ShellQuote(s1) + " " + ShellQuote(s2),
                                     b.tmp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(Has(r.err, "S0of3.json")) << r.err;
  EXPECT_EQ(ReadText(s0), before);
}

TEST(ShardMerge, ShardOptionIsChecked) {
  Batch b;
  for (const char* bad : {"3/3", "1", "a/2", "0/0", "-1/2", "1/2x", "1/"}) {
    const CommandResult r = RunImuconv("run " + ShellQuote(b.pipeline) + " " +
                                           ShellQuote(std::string("--shard=") + bad) + " -o " +
                                           ShellQuote(b.tmp.file("x.json")),
                                       b.tmp);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_TRUE(Has(r.err, "--shard: expected K/N")) << bad << ": " << r.err;
    EXPECT_FALSE(fs::exists(b.tmp.file("x.json")));
  }
  const CommandResult npz = RunImuconv(
      "run " + ShellQuote(b.pipeline) + " --shard 0/2 -o " + ShellQuote(b.tmp.file("x.npz")),
      b.tmp);
  EXPECT_EQ(npz.exit_code, 2);
  EXPECT_TRUE(Has(npz.err, "not --format npz")) << npz.err;
}

}  // namespace
