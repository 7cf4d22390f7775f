// The integrity of the shards of imuconv run --shard K/N (issue 22): each records the FNV-1a 64
// of its own content in its last member, "shard_fnv1a_64", and imuconv merge checks it, every
// count the shard states against its size, and reads its "shard" member through the one JSON
// reader, before anything is written. A shard with one byte removed or one number changed was
// merged into invalid JSON or a wrong document with exit 0; now each is refused with exit 2,
// naming the file, and no output is left. The merge of intact shards stays the whole run's bytes
// (shard_merge.cpp checks that in depth).
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <string>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "euroc_slice.h"
#include "shard_forgery.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

/// Three tasks in three units over 1 s of the bundled EuRoC slice each: three small shards.
struct SmallBatch {
  TempDir tmp;
  std::string pipeline;
  SmallBatch() {
    CopyEurocSlice(tmp);
    json tasks = json::array();
    for (int k = 0; k < 3; ++k)
      tasks.push_back({{"type", "preintegrate"},
                       {"name", "kf" + std::to_string(k)},
                       {"method", {{"propagator", "rk4"}}},
                       {"conventions", {"gtsam_manifold"}},
                       {"bias", "ground_truth"},
                       {"keyframes", {{"start", 1.0 * k}, {"end", 1.0 * k + 1.0}, {"step", 0.5}}}});
    const json p = EurocSlicePipeline(tasks);
    pipeline = tmp.write("P.json", p.dump(2));
  }
  std::string run(const std::string& extra, const std::string& out) {
    const CommandResult r = RunImuconv(
        "-q run " + ShellQuote(pipeline) + " " + extra + " -o " + ShellQuote(tmp.file(out)), tmp);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return tmp.file(out);
  }
  std::string shard(unsigned k) {
    return run("--shard " + std::to_string(k) + "/3", "S" + std::to_string(k) + ".json");
  }
  CommandResult merge(const std::vector<std::string>& shards) {
    std::string args = "merge -o " + ShellQuote(tmp.file("out.json"));
    for (const auto& s : shards) args += " " + ShellQuote(s);
    return RunImuconv(args, tmp);
  }
  /// The merge must fail: exit 2, `file` and `why` in the message, no output, nothing new.
  void refused(const std::vector<std::string>& shards, const std::string& file,
               const std::string& why) {
    const std::size_t before = tmp.entries();
    const CommandResult r = merge(shards);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(Has(r.err, file)) << r.err;
    EXPECT_TRUE(Has(r.err, why)) << r.err;
    EXPECT_FALSE(Has(r.err, "[json.exception")) << r.err;
    EXPECT_FALSE(fs::exists(tmp.file("out.json")));
    EXPECT_EQ(tmp.entries(), before);
  }
};

TEST(ShardIntegrity, IntactShardsStillMergeToTheWholeRunsBytes) {
  SmallBatch b;
  const std::string whole = ReadText(b.run("", "whole.json"));
  const std::string s1 = ReadText(b.shard(1));
  // The last member: 16 hexadecimal digits, not in the whole run's document.
  EXPECT_TRUE(Has(s1, ",\n  \"shard_fnv1a_64\": \"")) << s1.substr(s1.size() - 80);
  EXPECT_FALSE(Has(whole, "shard_fnv1a_64"));
  // What it records is the FNV-1a 64 of the bytes before it (an independent implementation).
  EXPECT_EQ(ResealRunShard(s1), s1);
  const CommandResult r = b.merge({b.shard(2), b.shard(0), b.tmp.file("S1.json")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Byte identity, the claim of imuconv merge: no tolerance.
  EXPECT_EQ(ReadText(b.tmp.file("out.json")), whole);
}

TEST(ShardIntegrity, AShardWithOneByteRemovedIsRefused) {
  SmallBatch b;
  const std::string s0 = b.shard(0), s1 = b.shard(1), s2 = b.shard(2);
  std::string text = ReadText(s1);
  // One digit removed from the middle of a number inside the elements: still bracket-balanced.
  const std::size_t tasks = text.find("\"tasks\": [");
  ASSERT_NE(tasks, std::string::npos);
  const std::size_t digit = text.find_first_of("123456789", text.find("\"dt\"", tasks));
  ASSERT_NE(digit, std::string::npos);
  text.erase(digit, 1);
  b.tmp.write("cut.json", text);
  b.refused({s0, b.tmp.file("cut.json"), s2}, "cut.json",
            "does not match the FNV-1a 64 hash in /shard_fnv1a_64");
}

TEST(ShardIntegrity, AShardWithOneNumberChangedIsRefused) {
  SmallBatch b;
  const std::string s0 = b.shard(0), s1 = b.shard(1), s2 = b.shard(2);
  std::string text = ReadText(s1);
  // The last digit of the last number before the closing bracket: same length, same layout.
  const std::size_t end = text.rfind("\n  ]");
  const std::size_t digit = text.find_last_of("0123456789", end);
  text[digit] = text[digit] == '1' ? '2' : '1';
  b.tmp.write("edited.json", text);
  b.refused({s0, b.tmp.file("edited.json"), s2}, "edited.json", "is corrupted or was edited");
  // Its hash member changed instead of the content: the same refusal.
  std::string hash_edited = ReadText(s1);
  const std::size_t hex = hash_edited.rfind("\"shard_fnv1a_64\": \"") + 19;
  hash_edited[hex] = hash_edited[hex] == '0' ? '1' : '0';
  b.tmp.write("hash.json", hash_edited);
  b.refused({s0, b.tmp.file("hash.json"), s2}, "hash.json", "is corrupted or was edited");
  // No hash member at all (a shard of an imuconv before this check): refused, saying what is
  // missing.
  const std::string old = ReadText(s2);
  const std::size_t member = old.rfind(",\n  \"shard_fnv1a_64\"");
  b.tmp.write("old.json", old.substr(0, member) + "\n}\n");
  b.refused({s0, s1, b.tmp.file("old.json")}, "old.json", "expected the member \"shard_fnv1a_64\"");
}

TEST(ShardIntegrity, AResealedShardWhoseTaskCountIsWrongIsRefused) {
  // The hash is right (recomputed after the edit), the "shard" member is not: it says the shard
  // holds tasks [1, 3) of 3 where it holds task 1 only. The element scan refuses it.
  SmallBatch b;
  const std::string s0 = b.shard(0), s1 = b.shard(1);
  std::string text = ReadText(s1);
  ASSERT_TRUE(ReplaceFirst(text, "\"end_task\": 2", "\"end_task\": 3"));
  b.tmp.write("forged.json", ResealRunShard(text));
  b.refused({s0, b.tmp.file("forged.json")}, "forged.json", "expected task 2's element here");
}

TEST(ShardIntegrity, AShardMemberThatIsNotJsonIsNamedWithoutTheLibrarysWords) {
  // Bracket-balanced but not JSON: a leading zero. Before, nlohmann's
  // "[json.exception.parse_error.101]" reached the user.
  SmallBatch b;
  const std::string s0 = b.shard(0);
  std::string text = ReadText(s0);
  ASSERT_TRUE(ReplaceFirst(text, "\"index\": 0", "\"index\": 00"));
  b.tmp.write("zero.json", ResealRunShard(text));
  b.refused({b.tmp.file("zero.json")}, "zero.json",
            "its \"shard\" member is not JSON as imuconv writes it");
}

TEST(ShardIntegrity, CountsAreCheckedAgainstTheFileBeforeAnythingIsAllocated) {
  SmallBatch b;
  const std::string s0 = b.shard(0);
  {
    SCOPED_TRACE("300,000,000 shards");
    // The old merge sized a table by this count first: 2.4 GB of pointers for a 10 KB file.
    std::string text = ReadText(s0);
    ASSERT_TRUE(ReplaceFirst(text, "\"count\": 3", "\"count\": 300000000"));
    b.tmp.write("many.json", ResealRunShard(text));
    rusage before{};
    getrusage(RUSAGE_CHILDREN, &before);
    b.refused({b.tmp.file("many.json")}, "many.json",
              "missing 299999999 of the 300000000 shards (index 1, 2,");
    rusage after{};
    getrusage(RUSAGE_CHILDREN, &after);
    // ru_maxrss (KiB) is the largest of every child so far; the runs before it (a shard of 1 s
    // of data) stay far below 512 MiB, as does a merge of a 10 KB shard (tens of MB, more under
    // ASan), where the old table alone was 2.4 GB: the bound tells the two apart with margin.
    EXPECT_LT(after.ru_maxrss, 512L * 1024) << "a merge held more memory than a small shard needs";
  }
  {
    SCOPED_TRACE("more elements than bytes");
    std::string text = ReadText(s0);
    for (const auto& [key, value] :
         {std::pair<std::string, std::string>{"\"end_task\": 1", "\"end_task\": 300000000"},
          {"\"tasks\": 3", "\"tasks\": 300000000"}}) {
      ASSERT_TRUE(ReplaceFirst(text, key, value)) << key;
    }
    b.tmp.write("long.json", ResealRunShard(text));
    b.refused({b.tmp.file("long.json")}, "long.json",
              "says it holds 300000000 task elements, more than its");
  }
}

}  // namespace
