// FindEmptyInterval (imuconv/pipeline/interval_samples.h), the one rule on intervals without a
// sample that `imuconv run` (ends included) and optimize's factors (a sample strictly inside)
// share, on samples and keyframes small enough to check by hand.
#include "imuconv/pipeline/interval_samples.h"

#include <gtest/gtest.h>

#include <vector>

namespace {

using imuconv::ImuSample;
using imuconv::pipeline::FindEmptyInterval;
using imuconv::pipeline::IntervalEnds;

std::vector<ImuSample> SamplesAt(const std::vector<double>& times) {
  std::vector<ImuSample> s(times.size());
  for (std::size_t i = 0; i < times.size(); ++i) s[i].t = times[i];
  return s;
}

std::optional<std::size_t> FirstEmptyInterval(const std::vector<double>& samples,
                                              const std::vector<double>& keyframes,
                                              IntervalEnds ends) {
  const auto e = FindEmptyInterval(
      SamplesAt(samples), keyframes.size(), [&](std::size_t k) { return keyframes[k]; }, ends);
  if (!e) return std::nullopt;
  EXPECT_EQ(e->t_start, keyframes[e->index]);
  EXPECT_EQ(e->t_end, keyframes[e->index + 1]);
  return e->index;
}

TEST(IntervalSamples, KeyframesOnTheSamplesHoldThemOnlyWithTheEnds) {
  const std::vector<double> s = {0, 1, 2, 3};
  EXPECT_EQ(FirstEmptyInterval(s, {0, 1, 2, 3}, IntervalEnds::kIncluded), std::nullopt);
  EXPECT_EQ(FirstEmptyInterval(s, {0, 1, 2, 3}, IntervalEnds::kExcluded), 0u);
  EXPECT_EQ(FirstEmptyInterval(s, {0, 1.5, 3}, IntervalEnds::kExcluded), std::nullopt);
  // Within kSameInstant (1 ns) of an end is at that end: not inside.
  EXPECT_EQ(FirstEmptyInterval({0, 0.5, 1 + 5e-10, 2}, {0, 1, 2}, IntervalEnds::kExcluded), 1u);
  EXPECT_EQ(FirstEmptyInterval({0, 0.5, 1 + 5e-9, 2}, {0, 1, 2}, IntervalEnds::kExcluded),
            std::nullopt);
}

TEST(IntervalSamples, AnIntervalBetweenTwoSamplesOrInAGapHoldsNone) {
  EXPECT_EQ(FirstEmptyInterval({0, 1, 2}, {0, 0.25, 0.5, 2}, IntervalEnds::kIncluded), 1u);
  // Samples to 2, a gap, samples from 10: [2, 4] holds the sample at its start, [4, 6] none.
  const std::vector<double> gap = {0, 1, 2, 10, 11, 12};
  const std::vector<double> kf = {0, 2, 4, 6, 8, 10, 12};
  EXPECT_EQ(FirstEmptyInterval(gap, kf, IntervalEnds::kIncluded), 2u);
  EXPECT_EQ(FirstEmptyInterval(gap, kf, IntervalEnds::kExcluded), 1u);
}

TEST(IntervalSamples, IntervalsOutsideTheDataAreLeftToTheOtherChecks) {
  EXPECT_EQ(FirstEmptyInterval({1, 2, 3}, {-5, -4, 1.5, 2.5, 7, 8}, IntervalEnds::kExcluded),
            std::nullopt);
  EXPECT_EQ(FirstEmptyInterval({1, 2, 3}, {1.5}, IntervalEnds::kExcluded), std::nullopt);
}

}  // namespace
