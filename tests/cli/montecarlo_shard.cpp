// imuconv montecarlo --shard K/N -o FILE and imuconv montecarlo --merge: the N shard files of a
// run, merged in any order, give what one unsharded run gives, byte for byte (its --json, its
// text summary, its --report page, its exit code), for an even and an uneven split, one shard,
// and more shards than trials (some empty); a hostile merge (a shard missing, given twice, of
// another run or split or CPU kernel instance, truncated, corrupted, with bytes after its end, not
// a shard) exits 2 naming the file and prints nothing; misused options are refused before any work.
//
// The reference is always a whole run of the same command in the same test (another process,
// another thread count), never text copied from our own output. The runs use the first 1 s of
// smooth-0 (201 samples) and tens of trials: the statistics do not matter here, their bits do.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv::test;

/// One montecarlo configuration: the whole run, its shards, and merges of them.
struct McRun {
  TempDir tmp;
  std::string base;  ///< the options every process of the run shares
  explicit McRun(int trials, int seed = 7, const std::string& method = "rk4") {
    base = "montecarlo --case " + ShellQuote(DataPath("reference/cases/smooth-0.json")) +
           " --method " + method + " --trials " + std::to_string(trials) + " --seed " +
           std::to_string(seed) + " --duration 1";
  }
  CommandResult whole(const std::string& extra) {
    return RunImuconv(base + " --threads 2 " + extra, tmp);
  }
  /// Shard k of n into <prefix><k>of<n>.mcs, on k + 1 threads (the thread count must not matter).
  std::string shard(int k, int n, const std::string& prefix = "S") {
    const std::string out =
        tmp.file(prefix + std::to_string(k) + "of" + std::to_string(n) + ".mcs");
    const CommandResult r =
        RunImuconv(base + " --threads " + std::to_string(k % 3 + 1) + " --shard " +
                       std::to_string(k) + "/" + std::to_string(n) + " -o " + ShellQuote(out),
                   tmp);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return out;
  }
  std::vector<std::string> shards(int n) {
    std::vector<std::string> s;
    for (int k = 0; k < n; ++k) s.push_back(shard(k, n));
    return s;
  }
  CommandResult merge(const std::vector<std::string>& files, const std::string& extra = "") {
    std::string args = "montecarlo " + extra + " --merge";
    for (const auto& f : files) args += " " + ShellQuote(f);
    return RunImuconv(args, tmp);
  }
};

/// Every output face of the merge equals the whole run's.
void ExpectSameAsWhole(McRun& run, const std::vector<std::string>& files) {
  const CommandResult whole_json = run.whole("--json"), merged_json = run.merge(files, "--json");
  EXPECT_EQ(merged_json.exit_code, whole_json.exit_code) << merged_json.err;
  EXPECT_TRUE(whole_json.exit_code == 0 || whole_json.exit_code == 1) << whole_json.err;
  EXPECT_EQ(merged_json.out, whole_json.out);
  EXPECT_TRUE(Has(whole_json.out, "\"nees_mean\""));
  const CommandResult whole_text = run.whole(""), merged_text = run.merge(files);
  EXPECT_EQ(merged_text.exit_code, whole_text.exit_code) << merged_text.err;
  EXPECT_EQ(merged_text.out, whole_text.out);
  EXPECT_TRUE(Has(whole_text.out, "verdict: "));
}

TEST(MontecarloShard, ShardsMergeToTheWholeRunsBytes) {
  // 41 trials: 3 shards hold [0, 13), [13, 27), [27, 41) (uneven); 1 shard holds them all.
  McRun run(41);
  std::vector<std::string> three = run.shards(3);
  const CommandResult shown =
      RunImuconv(run.base + " --shard 1/3 -o " + ShellQuote(run.tmp.file("again.mcs")), run.tmp);
  EXPECT_TRUE(Has(shown.out, "trials [13, 27) of 41")) << shown.out;
  // Any order on the command line.
  ExpectSameAsWhole(run, {three[2], three[0], three[1]});
  ExpectSameAsWhole(run, run.shards(1));
  // The HTML page too (it names the case by the path the shards recorded).
  const CommandResult whole = run.whole("--report " + ShellQuote(run.tmp.file("whole.html")));
  const CommandResult merged =
      run.merge(three, "--report " + ShellQuote(run.tmp.file("merged.html")));
  EXPECT_TRUE(whole.exit_code == 0 || whole.exit_code == 1) << whole.err;
  EXPECT_EQ(merged.exit_code, whole.exit_code) << merged.err;
  EXPECT_EQ(ReadText(run.tmp.file("merged.html")), ReadText(run.tmp.file("whole.html")));
  EXPECT_FALSE(ReadText(run.tmp.file("whole.html")).empty());
}

TEST(MontecarloShard, FullAndMeanOnlyPathsMergeToo) {
  // basalt runs every trial through its plugin ("full"), manifold through the core's kernel
  // ("mean_only"); both are trial paths the shards must reproduce.
  for (const auto& [method, path] :
       {std::pair<const char*, const char*>{"basalt", "\"trial_path\": \"full\""},
        {"manifold", "\"trial_path\": \"mean_only\""}}) {
    McRun run(20, 3, method);
    EXPECT_TRUE(Has(run.whole("--json").out, path)) << method;
    ExpectSameAsWhole(run, run.shards(4));
  }
}

TEST(MontecarloShard, MoreShardsThanTrialsLeavesSomeEmpty) {
  // 17 trials in 20 shards: [floor(k 17 / 20), floor((k+1) 17 / 20)) leaves 3 of them empty
  // (shard 0 among them); each is still written, and still needed by the merge.
  McRun run(17);
  const std::vector<std::string> files = run.shards(20);
  const CommandResult empty =
      RunImuconv(run.base + " --shard 0/20 -o " + ShellQuote(run.tmp.file("e.mcs")), run.tmp);
  EXPECT_TRUE(Has(empty.out, "trials [0, 0) of 17")) << empty.out;
  ExpectSameAsWhole(run, files);
  // With this seed the 17-trial run is inconsistent (exit 1): the merge carries that verdict too.
  EXPECT_EQ(run.merge(files).exit_code, 1);
  const CommandResult missing = run.merge({files.begin(), files.end() - 1});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_TRUE(Has(missing.err, "missing 1 of the 20 shards (index 19)")) << missing.err;
}

/// A merge of `files` exits 2, prints nothing, and says `what` about `named`.
void ExpectShardsRefused(McRun& run, const std::vector<std::string>& files,
                         const std::string& named, const std::string& what) {
  const CommandResult r = run.merge(files, "--json");
  EXPECT_EQ(r.exit_code, 2) << named << ": " << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_TRUE(Has(r.err, named)) << r.err;
  EXPECT_TRUE(Has(r.err, what)) << r.err;
}

TEST(MontecarloShard, HostileMergesAreRefused) {
  McRun run(41);
  const std::vector<std::string> s = run.shards(3);
  const std::string text = ReadText(s[1]);

  ExpectShardsRefused(run, {s[0], s[2]}, "missing 1 of the 3 shards (index 1)",
                      "every shard K/N of the run is needed");
  ExpectShardsRefused(run, {s[0], s[1], s[1], s[2]}, "shard 1 of 3 is given twice", "S1of3.mcs");
  // Another copy of the same shard under another name is still a duplicate.
  const std::string copy = run.tmp.write("copy.mcs", text);
  ExpectShardsRefused(run, {s[0], s[1], copy, s[2]}, "copy.mcs", "given twice");

  // Foreign: another seed, another method, another split.
  McRun other_seed(41, 8);
  const std::string foreign = other_seed.shard(1, 3, "F");
  const std::string foreign_here = run.tmp.write("F1of3.mcs", ReadText(foreign));
  ExpectShardsRefused(run, {s[0], foreign_here, s[2]}, "F1of3.mcs",
                      "not shards of one run: their /run/seed differ (8 and 7)");
  McRun other_method(41, 7, "euler");
  const std::string euler = run.tmp.write("E1of3.mcs", ReadText(other_method.shard(1, 3, "E")));
  ExpectShardsRefused(run, {s[0], euler, s[2]}, "E1of3.mcs", "not shards of one run: their /run/");
  const std::string half = run.shard(0, 2, "H");
  ExpectShardsRefused(run, {s[0], half, s[2]}, "H0of2.mcs", "one is shard 0 of 2, the other of 3");

  // Truncated: inside the header, inside the errors, without its hash line.
  const std::size_t header_end = text.find('\n', text.find('\n') + 1);
  ASSERT_NE(header_end, std::string::npos);
  ExpectShardsRefused(run, {s[0], run.tmp.write("t1.mcs", text.substr(0, header_end / 2)), s[2]},
                      "t1.mcs", "ends inside its header line");
  ExpectShardsRefused(run,
                      {s[0], run.tmp.write("t2.mcs", text.substr(0, header_end + 1 + 500)), s[2]},
                      "t2.mcs", "is truncated");
  ExpectShardsRefused(run, {s[0], run.tmp.write("t3.mcs", text.substr(0, text.size() - 1)), s[2]},
                      "t3.mcs", "is truncated");
  ExpectShardsRefused(run, {s[0], run.tmp.write("long.mcs", text + "x"), s[2]}, "long.mcs",
                      "bytes after its end");

  // Corrupted: one bit of one end error; one digit of the predicted covariance in the header
  // (the JSON is still valid; the other shards disagree); the hash line.
  std::string flipped = text;
  flipped[header_end + 1 + 700] ^= 0x01;
  ExpectShardsRefused(run, {s[0], run.tmp.write("c1.mcs", flipped), s[2]}, "c1.mcs",
                      "is corrupted");
  std::string header_digit = text;
  const std::size_t pred = header_digit.find("\"predicted\":[\"0x1.");
  ASSERT_NE(pred, std::string::npos);
  char& digit = header_digit[pred + 18];
  digit = digit == '0' ? '1' : '0';
  ExpectShardsRefused(run, {s[0], run.tmp.write("c2.mcs", header_digit), s[2]}, "c2.mcs",
                      "not shards of one run: their /run/predicted differ");
  // A shard from a CPU whose kernel instance rounds differently (FMA or not): its trials'
  // last bits would differ from this one's, so the merge names the instance instead of joining.
  std::string other_cpu = text;
  const std::size_t instance = other_cpu.find("\"kernel_instance\":\"");
  ASSERT_NE(instance, std::string::npos);
  const std::size_t name = instance + std::string("\"kernel_instance\":\"").size();
  const std::string here = other_cpu.substr(name, other_cpu.find('"', name) - name);
  const std::string there = here == "baseline" ? "avx2" : "baseline";
  other_cpu.replace(name, here.size(), there);
  ExpectShardsRefused(run, {s[0], run.tmp.write("cpu.mcs", other_cpu), s[2]}, "cpu.mcs",
                      "not shards of one run: their /run/kernel_instance differ");
  std::string hash = text;
  hash[hash.size() - 2] = hash[hash.size() - 2] == '0' ? '1' : '0';
  ExpectShardsRefused(run, {s[0], run.tmp.write("c3.mcs", hash), s[2]}, "c3.mcs", "is corrupted");

  // Not a shard: the whole run's JSON output, an empty file, a directory, no such file.
  const std::string json = run.tmp.write("whole.json", run.whole("--json").out);
  ExpectShardsRefused(run, {json}, "whole.json", "not a montecarlo shard");
  ExpectShardsRefused(run, {run.tmp.write("empty.mcs", "")}, "empty.mcs", "not a montecarlo shard");
  ExpectShardsRefused(run, {run.tmp.path()}, run.tmp.path(), "is not a regular file");
  ExpectShardsRefused(run, {run.tmp.file("nothing.mcs")}, "nothing.mcs", "cannot be read");
  // Another version of the format.
  std::string v2 = text;
  v2.replace(0, std::string("imuconv montecarlo shard 1").size(), "imuconv montecarlo shard 2");
  ExpectShardsRefused(run, {run.tmp.write("v2.mcs", v2)}, "v2.mcs", "another format version");
}

TEST(MontecarloShard, CorruptedHeaderDigitIsNamed) {
  // A digit of the predicted covariance changed in the header of the only shard: nothing to
  // compare it with but its own hash, which refuses it.
  McRun run(20);
  std::string text = ReadText(run.shard(0, 1));
  const std::size_t pred = text.find("\"predicted\":[\"0x1.");
  ASSERT_NE(pred, std::string::npos);
  text[pred + 18] = text[pred + 18] == '0' ? '1' : '0';
  const CommandResult r = run.merge({run.tmp.write("c.mcs", text)});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "c.mcs: is corrupted")) << r.err;
}

TEST(MontecarloShard, OptionsAreChecked) {
  McRun run(41);
  const std::string out = run.tmp.file("x.mcs");
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {run.base + " --shard 1/3", "--shard K/N needs -o FILE"},
      {run.base + " --shard 3/3 -o " + ShellQuote(out), "--shard: expected K/N with 0 <= K < N"},
      {run.base + " --shard 1/0 -o " + ShellQuote(out), "--shard: expected K/N"},
      {run.base + " --shard=-1/3 -o " + ShellQuote(out), "--shard: expected K/N"},
      {run.base + " --shard 1/3 --json -o " + ShellQuote(out),
       "--json and --report go with --merge"},
      {run.base + " -o " + ShellQuote(out), "-o is the shard file of --shard K/N"},
      {run.base + " --shard 0/3 -o " + ShellQuote(run.tmp.path()), run.tmp.path()},
      {run.base + " --shard 0/3 -o " + ShellQuote(DataPath("reference/cases/smooth-0.json")),
       "the case file"},
      {"montecarlo --merge " + ShellQuote(out) + " --seed 3", "--seed is not used with it"},
      {"montecarlo --merge " + ShellQuote(out) + " --threads 2", "--threads is not used with it"},
      {"montecarlo --merge " + ShellQuote(out) + " --duration 2", "--duration is not used with it"},
      {"montecarlo --method rk4 --trials 20 --seed 1",
       "--case (or --pipeline): required (or --merge SHARD...)"},
  };
  for (const Case& c : cases) {
    const CommandResult r = RunImuconv(c.args, run.tmp);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_TRUE(Has(r.err, c.message)) << c.args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.args;
  }
  // A shard whose run fails (too few trials) writes nothing, and leaves no temporary.
  const std::size_t before = run.tmp.entries();
  const CommandResult few =
      RunImuconv("montecarlo --case " + ShellQuote(DataPath("reference/cases/smooth-0.json")) +
                     " --method rk4 --trials 5 --seed 1 --shard 0/2 -o " + ShellQuote(out),
                 run.tmp);
  EXPECT_EQ(few.exit_code, 2);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(run.tmp.entries(), before);
  // The pipeline merge points a montecarlo shard to its own merge.
  const std::string shard = run.shard(0, 1);
  const CommandResult r = RunImuconv(
      "merge -o " + ShellQuote(run.tmp.file("m.json")) + " " + ShellQuote(shard), run.tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "imuconv montecarlo --merge")) << r.err;
  EXPECT_FALSE(fs::exists(run.tmp.file("m.json")));
}

}  // namespace
