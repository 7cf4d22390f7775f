// imuconv montecarlo --merge on forged shards (issue 22): the header line is read through the
// one JSON reader (its nesting bound; no "[json.exception...]" in a message), a number the
// header holds must be finite, and a statistic that is not finite is an error (exit 2, naming
// the shards), never a verdict with a reason that does not hold ("the predicted covariance is
// too large"). Each forged shard has its hash line recomputed (shard_forgery.h), so that what is
// tested is the check behind the hash.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"
#include "shard_forgery.h"

namespace {
using namespace imuconv::test;

/// One shard (0 of 1) of 16 trials over the first 0.2 s of smooth-0: its text.
struct OneShard {
  TempDir tmp;
  std::string text;
  OneShard() {
    const std::string out = tmp.file("S.mcs");
    const CommandResult r = RunImuconv(
        "montecarlo --case " + ShellQuote(DataPath("reference/cases/smooth-0.json")) +
            " --method rk4 --trials 16 --seed 3 --duration 0.2 --shard 0/1 -o " + ShellQuote(out),
        tmp);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    text = ReadText(out);
  }
  /// Where line 3 (the trials' end errors) begins.
  std::size_t payload() const { return text.find('\n', text.find('\n') + 1) + 1; }
  /// Merges `forged` (resealed) as F.mcs; the merge must be refused naming it and saying `why`.
  void refused(const std::string& forged, const std::string& why) {
    const std::string file = tmp.write("F.mcs", ResealMontecarloShard(forged));
    const CommandResult r = RunImuconv("montecarlo --merge " + ShellQuote(file), tmp);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_TRUE(Has(r.err, "F.mcs")) << r.err;
    EXPECT_TRUE(Has(r.err, why)) << r.err;
    EXPECT_FALSE(Has(r.err, "[json.exception")) << r.err;
    EXPECT_EQ(r.out, "");  // no verdict
  }
};

TEST(MontecarloShardHostile, TheIntactShardMerges) {
  OneShard s;
  const std::string file = s.tmp.write("F.mcs", ResealMontecarloShard(s.text));
  EXPECT_EQ(ReadText(file), s.text);  // the independent hash agrees with imuconv's
  const CommandResult r = RunImuconv("montecarlo --merge " + ShellQuote(file), s.tmp);
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;
  EXPECT_TRUE(Has(r.out, "verdict: ")) << r.out;
}

TEST(MontecarloShardHostile, AHeaderNested200000DeepIsRefusedNotACrash) {
  // Before: the header parsed, and copying its "run" object recursed 200,000 levels deep (a
  // stack overflow, SIGSEGV). The nesting is inside /run, where the copy went.
  OneShard s;
  const std::size_t run = s.text.find("\"run\":{");
  ASSERT_NE(run, std::string::npos);
  const std::string deep = "\"deep\":" + std::string(200000, '[') + std::string(200000, ']') + ",";
  std::string forged = s.text;
  forged.insert(run + 7, deep);
  s.refused(forged, "nested deeper than 256 levels");
}

TEST(MontecarloShardHostile, AHeaderThatIsNotJsonIsNamedWithoutTheLibrarysWords) {
  OneShard s;
  std::string forged = s.text;
  forged.insert(s.text.find("\"run\":{") + 7, "\"x\":01,");
  s.refused(forged, "its header line is not JSON as imuconv writes it");
}

TEST(MontecarloShardHostile, ANonFiniteNumberInTheHeaderIsRefusedAtItsPointer) {
  // A predicted covariance entry "nan" (strtod reads it): refused where it is.
  OneShard s;
  const std::string key = "\"predicted\":[\"";
  const std::size_t at = s.text.find(key);
  ASSERT_NE(at, std::string::npos);
  std::string forged = s.text;
  const std::size_t value = at + key.size();
  forged.replace(value, forged.find('"', value) - value, "nan");
  s.refused(forged, "/run/predicted/0: expected a finite number, found nan");
}

TEST(MontecarloShardHostile, ANonFiniteStatisticIsAnErrorNotAVerdict) {
  // End errors of +-1e300: finite, so the shard is well formed, but their squares overflow: the
  // sample covariance and the NEES are not finite. Before, the verdict said "inconsistent: ...
  // the predicted covariance is too large" (every comparison with NaN is false).
  OneShard s;
  std::string forged = s.text;
  const std::size_t begin = s.payload(), trials = 16, values = 15 * trials;
  for (std::size_t i = 0; i < values; ++i) {
    const double x = (i % 2 ? 1e300 : -1e300);
    unsigned char bytes[8];
    std::uint64_t u;
    std::memcpy(&u, &x, sizeof u);
    for (int b = 0; b < 8; ++b)
      bytes[b] = static_cast<unsigned char>(u >> (8 * b));  // little-endian, as the format says
    forged.replace(begin + 8 * i, 8, reinterpret_cast<const char*>(bytes), 8);
  }
  s.refused(forged, "is not finite");
}

}  // namespace
