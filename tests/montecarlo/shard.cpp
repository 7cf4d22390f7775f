// The montecarlo shard file (apps/montecarlo/shard.h) as a round trip: every double of the run
// (the predicted covariance, duration, noise scale, offset) and of the trials' end errors comes
// back with the same bits, for values chosen to break a decimal or a byte-order encoding
// (-0, the smallest subnormal, the largest finite, 1/3, values that differ in their last bit);
// and the split: for every T and N, the shards tile [0, T) in order, each within one trial of
// T / N. Exact equality is the requirement (the merge must give the whole run's bytes), so
// there is no tolerance.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "shard.h"

namespace {
using namespace imuconv;
using namespace imuconv::montecarlo;

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Awkward doubles, cycled through.
double Awkward(int i) {
  static const double values[] = {-0.0,
                                  std::numeric_limits<double>::denorm_min(),
                                  -std::numeric_limits<double>::denorm_min(),
                                  DBL_MAX,
                                  -DBL_MAX,
                                  DBL_MIN,
                                  1.0 / 3.0,
                                  std::nextafter(1.0 / 3.0, 1.0),
                                  0.1,
                                  -2.5e-300,
                                  6.02214076e23,
                                  1.0};
  constexpr int n = sizeof values / sizeof values[0];
  return values[i % n] * (i / n % 2 == 0 ? 1.0 : -1.0);
}

Result AwkwardHead() {
  Result r;
  r.method = "rk4";
  r.method_kind = "propagator";
  r.convention = "preint_reference";
  r.trials = 37;
  r.seed = 18446744073709551615ull;  // the largest seed: an unsigned 64-bit count survives JSON
  r.noise_scale = std::nextafter(1.0, 2.0);
  r.duration = 1.0 / 3.0;
  r.samples = 201;
  r.noise_model.simulated = "continuous";
  r.noise_model.matches = false;
  r.noise_model.note = "a note with \"quotes\", a tab\t and UTF-8: σ²";
  for (const char* b : {"theta", "p", "v", "bg", "ba"}) r.blocks.push_back(BlockRatio{b, 0.0, {}});
  r.trial_path = "mean_only";
  r.mean_only_offset = std::numeric_limits<double>::denorm_min();
  for (int i = 0; i < kDim * kDim; ++i) r.predicted(i / kDim, i % kDim) = Awkward(i);
  return r;
}

TEST(MontecarloShardFile, RunIdentityRoundTripsBitForBit) {
  const Result in = AwkwardHead();
  const nlohmann::json run = ShardRunJson(in, {{"imuconv_version", "test"}});
  // Through text, as the file carries it.
  const Result out = ResultFromRunJson(nlohmann::json::parse(run.dump()));
  EXPECT_EQ(out.method, in.method);
  EXPECT_EQ(out.method_kind, in.method_kind);
  EXPECT_EQ(out.convention, in.convention);
  EXPECT_EQ(out.trials, in.trials);
  EXPECT_EQ(out.seed, in.seed);
  EXPECT_EQ(out.samples, in.samples);
  EXPECT_EQ(out.noise_model.simulated, in.noise_model.simulated);
  EXPECT_EQ(out.noise_model.matches, in.noise_model.matches);
  EXPECT_EQ(out.noise_model.note, in.noise_model.note);
  EXPECT_EQ(out.trial_path, in.trial_path);
  ASSERT_EQ(out.blocks.size(), in.blocks.size());
  for (std::size_t b = 0; b < in.blocks.size(); ++b)
    EXPECT_EQ(out.blocks[b].block, in.blocks[b].block);
  EXPECT_TRUE(SameBits(out.noise_scale, in.noise_scale));
  EXPECT_TRUE(SameBits(out.duration, in.duration));
  EXPECT_TRUE(SameBits(out.mean_only_offset, in.mean_only_offset));
  for (int i = 0; i < kDim * kDim; ++i)
    EXPECT_TRUE(SameBits(out.predicted(i / kDim, i % kDim), in.predicted(i / kDim, i % kDim))) << i;
}

TEST(MontecarloShardFile, ErrorsRoundTripBitForBit) {
  const Result head = AwkwardHead();
  const nlohmann::json run = ShardRunJson(head, {{"imuconv_version", "test"}});
  test::TempDir tmp;
  // Shard 1 of 2 of 37 trials: [18, 37), 19 trials, 285 awkward doubles.
  const auto [first, end] = ShardTrials(head.trials, 1, 2);
  ASSERT_EQ(first, 18);
  ASSERT_EQ(end, 37);
  std::vector<Vec15> errors(static_cast<std::size_t>(end - first));
  for (std::size_t t = 0; t < errors.size(); ++t)
    for (int j = 0; j < kDim; ++j) errors[t][j] = Awkward(static_cast<int>(t) * kDim + j + 7);
  std::string bytes;
  WriteShard([&](std::string_view piece) { bytes.append(piece); }, 1, 2, first, end, run, errors);
  const std::string file = tmp.write("s.mcs", bytes);

  const ShardHeader h = ReadShardHeader(file);
  EXPECT_EQ(h.index, 1);
  EXPECT_EQ(h.count, 2);
  EXPECT_EQ(h.first, first);
  EXPECT_EQ(h.end, end);
  EXPECT_EQ(h.run, run);
  std::vector<Vec15> back(errors.size(), Vec15::Constant(42.0));
  ReadShardErrors(h, back.data());
  for (std::size_t t = 0; t < errors.size(); ++t)
    for (int j = 0; j < kDim; ++j) EXPECT_TRUE(SameBits(back[t][j], errors[t][j])) << t << " " << j;
  // The payload is little-endian whatever the host: the first error's first double,
  // Awkward(7) = nextafter(1/3, 1), byte by byte from the least significant.
  const std::size_t payload = static_cast<std::size_t>(h.payload_offset);
  std::uint64_t u;
  const double x = Awkward(7);
  std::memcpy(&u, &x, sizeof u);
  for (int b = 0; b < 8; ++b)
    EXPECT_EQ(static_cast<unsigned char>(bytes[payload + b]), (u >> (8 * b)) & 0xff) << b;
}

TEST(MontecarloShardFile, ShardsTileTheTrials) {
  for (int trials : {16, 17, 41, 1000, 10000000})
    for (int count : {1, 2, 3, 7, 20, 1000}) {
      int next = 0;
      for (int k = 0; k < count; ++k) {
        const auto [first, end] = ShardTrials(trials, k, count);
        EXPECT_EQ(first, next) << trials << " " << k << "/" << count;
        const int size = end - first;
        // floor((k+1) T / N) - floor(k T / N) is floor(T / N) or one more.
        EXPECT_TRUE(size == trials / count || size == trials / count + 1)
            << trials << " " << k << "/" << count;
        next = end;
      }
      EXPECT_EQ(next, trials) << trials << " " << count;
    }
}

}  // namespace
