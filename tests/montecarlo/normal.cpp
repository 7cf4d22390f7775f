// The generator of imuconv montecarlo's noise (apps/montecarlo/normal.h): its bits against
// published reference values, the ziggurat's tables against their defining equations, and
// its normals against N(0, 1) by moments, a binned chi-square test, the tail and
// independence between the trials' streams.
//
// Tolerances are k standard errors of the statistic under a correct N(0, 1) (stated at each
// check); with k = 5 a correct generator fails a check with probability below 1e-6, while
// the errors these guard against (a wrong layer, a lost sign, a tail drawn from the wrong
// place) move the statistics by tens of standard errors at these sample sizes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "../../apps/montecarlo/normal.h"
#include "../../apps/montecarlo/statistics.h"

namespace imuconv::montecarlo {
namespace {

// SplitMix64 from state 0: its published first outputs (the reference implementation's, as
// quoted by independent implementations' tests, e.g. the Go and C# golden tests).
TEST(MontecarloNormal, SplitMix64MatchesReferenceValues) {
  constexpr std::uint64_t kGamma = 0x9e3779b97f4a7c15ULL;
  EXPECT_EQ(SplitMix64(0), 0xe220a8397b1dcdafULL);
  EXPECT_EQ(SplitMix64(kGamma), 0x6e789e6aa1b965f4ULL);
  EXPECT_EQ(SplitMix64(2 * kGamma), 0x06c45d188009454fULL);
  EXPECT_EQ(SplitMix64(3 * kGamma), 0xf88bb8a8724c81ecULL);
  // Seeding takes exactly those four words as the state.
  Xoshiro256pp seeded(0), given({0xe220a8397b1dcdafULL, 0x6e789e6aa1b965f4ULL,
                                 0x06c45d188009454fULL, 0xf88bb8a8724c81ecULL});
  for (int k = 0; k < 100; ++k) ASSERT_EQ(seeded(), given()) << k;
}

// xoshiro256++ from the state {0, 0, 0, 1}: the first ten outputs of an independent
// implementation (DSCF-1224/xoshiro-fortran, test/README.md). The first is rotl(0 + 1, 23) by
// hand.
TEST(MontecarloNormal, Xoshiro256ppMatchesReferenceSequence) {
  Xoshiro256pp g(std::array<std::uint64_t, 4>{0, 0, 0, 1});
  const std::uint64_t expected[10] = {
      0x0000000000800000ULL, 0x0000000000800011ULL, 0x0002200000800011ULL, 0x0002200044000020ULL,
      0x00022000448008A1ULL, 0x01102100802208A0ULL, 0x0114002284200880ULL, 0x0402896644A64095ULL,
      0x8A14A0A244ACC891ULL, 0x8C88BA4680B20495ULL};
  for (int k = 0; k < 10; ++k) EXPECT_EQ(g(), expected[k]) << k;
}

// The layers' defining equations: every layer i >= 1 has area x_i (f_{i+1} - f_i) = v, the
// base r f(r) + tail = v, and the top layer closes at x_256 = 0. Rounding in the recursion
// grows to about 1e-13 relative over 255 layers (measured 1e-13 for the top layer), so 1e-11.
TEST(MontecarloNormal, ZigguratTablesSatisfyTheirEquations) {
  const ZigguratTables& z = ZigguratTables::Get();
  const double r = ZigguratTables::kR;
  EXPECT_NEAR(z.v, r * std::exp(-0.5 * r * r) + std::sqrt(M_PI / 2) * std::erfc(r / std::sqrt(2.0)),
              1e-18);
  EXPECT_NEAR(z.x[0] * z.f[0], z.v, 1e-18);  // the base's pseudo-rectangle
  for (int i = 1; i < ZigguratTables::kLayers; ++i) {
    EXPECT_NEAR(z.x[i] * (z.f[i + 1] - z.f[i]), z.v, 1e-11 * z.v) << "layer " << i;
    EXPECT_GT(z.x[i], z.x[i + 1]) << i;
    EXPECT_NEAR(z.f[i], std::exp(-0.5 * z.x[i] * z.x[i]), 1e-15) << i;
  }
}

// Fill gives the numbers repeated calls give, in order; a seed gives the same numbers.
TEST(MontecarloNormal, FillIsTheSequenceAndSeedsRepeat) {
  Normal a(42), b(42), c(43);
  std::vector<double> filled(1000);
  a.Fill(filled.data(), filled.size());
  int same_as_other_seed = 0;
  for (double x : filled) {
    EXPECT_EQ(x, b());
    same_as_other_seed += x == c();
  }
  EXPECT_EQ(same_as_other_seed, 0);
}

TEST(MontecarloNormal, DistributionIsStandardNormal) {
  constexpr int kN = 4000000;
  Normal normal(20261126);
  std::vector<double> x(kN);
  normal.Fill(x.data(), kN);

  // Moments. Standard errors for N(0,1): mean 1/sqrt(N), variance sqrt(2/N), third moment
  // sqrt(15/N), fourth moment sqrt(96/N) (var of x^4 = 105 - 9).
  double m1 = 0, m2 = 0, m3 = 0, m4 = 0;
  for (double v : x) {
    const double v2 = v * v;
    m1 += v;
    m2 += v2;
    m3 += v2 * v;
    m4 += v2 * v2;
  }
  m1 /= kN, m2 /= kN, m3 /= kN, m4 /= kN;
  std::printf("[ measured ] N = %d: mean %.2e, E x^2 %.5f, E x^3 %.2e, E x^4 %.4f\n", kN, m1, m2,
              m3, m4);
  EXPECT_NEAR(m1, 0.0, 5 / std::sqrt(kN));
  EXPECT_NEAR(m2, 1.0, 5 * std::sqrt(2.0 / kN));
  EXPECT_NEAR(m3, 0.0, 5 * std::sqrt(15.0 / kN));
  EXPECT_NEAR(m4, 3.0, 5 * std::sqrt(96.0 / kN));

  // 200 equiprobable bins of N(0, 1) (edges by the normal quantile, statistics.h, whose
  // 1e-9 accuracy moves a bin's probability by far less than its 1/sqrt(N/200) noise):
  // Pearson's statistic against chi-square(199) at the 1 - 1e-6 level. Bins this narrow see
  // a misplaced layer edge (0.4 % of the probability in a layer) as a 30-sigma excess.
  constexpr int kBins = 200;
  std::vector<double> edges(kBins - 1);
  for (int b = 1; b < kBins; ++b) edges[b - 1] = NormalQuantile(static_cast<double>(b) / kBins);
  std::vector<int> count(kBins, 0);
  for (double v : x) ++count[std::upper_bound(edges.begin(), edges.end(), v) - edges.begin()];
  const double expected = static_cast<double>(kN) / kBins;
  double pearson = 0;
  for (int c : count) pearson += (c - expected) * (c - expected) / expected;
  const double bound = ChiSquareQuantile(kBins - 1, 1 - 1e-6);
  std::printf("[ measured ] chi-square over %d bins: %.1f (bound %.1f)\n", kBins, pearson, bound);
  EXPECT_LT(pearson, bound);

  // The tail beyond r, drawn by its own path: P(|x| > r) = erfc(r / sqrt 2) = 2.58e-4, a
  // binomial count with standard deviation sqrt(N p); and beyond r + 1 (the tail's shape).
  const double r = ZigguratTables::kR;
  for (double t : {r, r + 1.0}) {
    const double p = std::erfc(t / std::sqrt(2.0));
    int beyond = 0, negative = 0;
    for (double v : x)
      if (std::abs(v) > t) ++beyond, negative += v < 0;
    std::printf("[ measured ] |x| > %.3f: %d (expected %.1f), %d negative\n", t, beyond, kN * p,
                negative);
    EXPECT_NEAR(beyond, kN * p, 5 * std::sqrt(kN * p) + 1) << t;
    EXPECT_NEAR(negative, 0.5 * beyond, 5 * std::sqrt(0.25 * beyond) + 1) << t;
  }
}

// The trials' streams (seeds SplitMix64(SplitMix64(seed) ^ i), montecarlo.cpp) are
// uncorrelated: the sample correlation of neighbouring trials' normals is within 5 standard
// errors 1/sqrt(n) of zero, for consecutive trial indices, where a weak seeding would show.
TEST(MontecarloNormal, NeighbouringTrialsAreUncorrelated) {
  constexpr int kN = 100000;
  std::vector<double> a(kN), b(kN);
  for (std::uint64_t i : {0ULL, 1ULL, 1000ULL}) {
    Normal(SplitMix64(SplitMix64(7) ^ i)).Fill(a.data(), kN);
    Normal(SplitMix64(SplitMix64(7) ^ (i + 1))).Fill(b.data(), kN);
    double ab = 0;
    for (int k = 0; k < kN; ++k) ab += a[k] * b[k];
    EXPECT_NEAR(ab / kN, 0.0, 5 / std::sqrt(kN)) << i;
  }
}

}  // namespace
}  // namespace imuconv::montecarlo
