// MakeWindow's one rule for knots and samples (core window.h, kSameInstant): a knot within
// 1 ns of a sample is that sample (its time and values, no interpolated knot beside it); a
// knot 2 ns away is not; an interval whose ends become one sample is an error. Synthetic
// samples at 200 Hz, times k / 200 as doubles.
#include <gtest/gtest.h>

#include <vector>

#include "imuconv/window.h"

namespace {
using namespace imuconv;

std::vector<ImuSample> Samples() {
  std::vector<ImuSample> s(101);
  for (std::size_t k = 0; k < s.size(); ++k) {
    s[k].t = static_cast<double>(k) / 200.0;
    s[k].gyro = Vec3(0.01 * k, 0.0, 0.0);
    s[k].accel = Vec3(0.0, 0.0, 9.81 + 0.001 * k);
  }
  return s;
}

TEST(KnotAtSample, ARoundingOffASampleIsThatSample) {
  const auto s = Samples();
  const double t_e = 3 * 0.1;  // 0.30000000000000004, the sample s[60] is at 0.3
  ASSERT_NE(t_e, s[60].t);
  SampleWindow w;
  ASSERT_TRUE(MakeWindow(s.data(), s.size(), 0.2, t_e, w).ok());
  // Knots: s[40] (0.2 exactly), s[41..59] inside, s[60] last: 21 knots, none interpolated.
  EXPECT_EQ(w.size(), 21u);
  EXPECT_EQ(w.t_start(), s[40].t);
  EXPECT_EQ(w.t_end(), s[60].t);  // exactly, not 4e-17 s beside it
  EXPECT_EQ(w[19].t, s[59].t);
  EXPECT_EQ(w.last.gyro, s[60].gyro);
  // The start side, and a knot a rounding before the first sample (not "not covered").
  ASSERT_TRUE(MakeWindow(s.data(), s.size(), 3 * 0.1, 0.4, w).ok());
  EXPECT_EQ(w.t_start(), s[60].t);
  EXPECT_EQ(w.size(), 21u);
  ASSERT_TRUE(MakeWindow(s.data(), s.size(), -1e-17, 0.1, w).ok());
  EXPECT_EQ(w.t_start(), 0.0);
}

TEST(KnotAtSample, TwoNanosecondsAwayIsInterpolated) {
  const auto s = Samples();
  SampleWindow w;
  ASSERT_TRUE(MakeWindow(s.data(), s.size(), 0.2, 0.3 + 2e-9, w).ok());
  EXPECT_EQ(w.t_end(), 0.3 + 2e-9);
  EXPECT_EQ(w.size(), 22u);  // s[60] is an interior knot, the end one more
}

TEST(KnotAtSample, EndsThatBecomeOneSampleAreAnError) {
  const auto s = Samples();
  SampleWindow w;
  const Status st = MakeWindow(s.data(), s.size(), 0.3 - 4e-10, 0.3 + 4e-10, w);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.message().find("shorter than a nanosecond"), std::string::npos) << st.message();
}

}  // namespace
