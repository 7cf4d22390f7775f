// Output numbers: the JSON writer's shortest double formatting (Schubfach) reads back to the
// same double and has the same digits as std::to_chars' shortest form, over the whole range
// (random bit patterns, subnormals, powers of two, "nice" decimals, edge cases).
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "../../apps/pipeline/src/double_format.h"
#include "imuconv/pipeline/json_writer.h"

namespace {
using imuconv::pipeline::FormatShortest;

std::string Format(double v) {
  char buf[64];
  return std::string(buf, FormatShortest(buf, v));
}

// The significant digits (no leading or trailing zeros) and the decimal exponent of the
// first one, of a number in any of the forms.
struct Digits {
  std::string d;
  int exp10 = 0;
  bool operator==(const Digits& o) const { return d == o.d && exp10 == o.exp10; }
};
Digits Parse(const std::string& s) {
  Digits out;
  std::size_t i = s[0] == '-' ? 1 : 0;
  int point = -1, pos = 0, ex = 0;
  for (; i < s.size() && s[i] != 'e'; ++i) {
    if (s[i] == '.') {
      point = pos;
      continue;
    }
    out.d += s[i];
    ++pos;
  }
  if (point < 0) point = pos;
  if (i < s.size()) ex = std::stoi(s.substr(i + 1));
  std::size_t lead = 0;
  while (lead < out.d.size() && out.d[lead] == '0') {
    ++lead;
    --point;
  }
  out.d = out.d.substr(lead);
  while (!out.d.empty() && out.d.back() == '0') out.d.pop_back();
  out.exp10 = point + ex;
  return out;
}

// Round trip and the same shortest digits as std::to_chars; the failure message names v.
::testing::AssertionResult Check(double v) {
  const std::string s = Format(v);
  double back = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), back);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size() || std::memcmp(&back, &v, sizeof v) != 0)
    return ::testing::AssertionFailure() << s << " does not read back to " << std::hexfloat << v;
  char ref[64];
  const std::string want(ref, std::to_chars(ref, ref + sizeof ref, v, std::chars_format::scientific).ptr);
  if (v != 0.0 && !(Parse(s) == Parse(want)))
    return ::testing::AssertionFailure() << s << " has other digits than std::to_chars' " << want;
  return ::testing::AssertionSuccess();
}

TEST(NumberFormat, Layout) {
  // nlohmann::json's layout: fixed from 1e-5 up to 1e15, integral values with ".0".
  EXPECT_EQ(Format(0.0), "0.0");
  EXPECT_EQ(Format(-0.0), "-0.0");
  EXPECT_EQ(Format(1.0), "1.0");
  EXPECT_EQ(Format(-2.0), "-2.0");
  EXPECT_EQ(Format(0.1), "0.1");
  EXPECT_EQ(Format(123.5), "123.5");
  EXPECT_EQ(Format(0.0001), "0.0001");
  EXPECT_EQ(Format(1e-05), "1e-05");
  EXPECT_EQ(Format(1.5e-07), "1.5e-07");
  EXPECT_EQ(Format(1e15), "1e+15");
  EXPECT_EQ(Format(123456789012345.0), "123456789012345.0");
  EXPECT_EQ(Format(1.5e20), "1.5e+20");
  EXPECT_EQ(Format(1.7976931348623157e308), "1.7976931348623157e+308");
  EXPECT_EQ(Format(5e-324), "5e-324");
  EXPECT_EQ(Format(1e-323), "1e-323");
  EXPECT_EQ(Format(-9.81), "-9.81");
  EXPECT_EQ(Format(145.595000064), "145.595000064");
  // The writer uses it for every number.
  std::string out;
  imuconv::pipeline::JsonWriter w(out);
  const double xs[] = {0.0, 1.0, 0.1, 1e-05};
  w.numbers(xs, 4);
  EXPECT_EQ(out, "[0.0, 1.0, 0.1, 1e-05]");
}

TEST(NumberFormat, EdgeCases) {
  const double lim_max = std::numeric_limits<double>::max(), lim_min = std::numeric_limits<double>::min(),
               denorm = std::numeric_limits<double>::denorm_min();
  for (double v : {lim_max, lim_min, denorm, 2 * denorm, 3 * denorm, 16 * denorm, std::nextafter(lim_min, 0.0),
                   9007199254740991.0, 9007199254740992.0, 9007199254740993.0, 1e22, 1e23, 5e-324, 0.3, 2.2250738585072009e-308,
                   std::nextafter(1.0, 2.0), std::nextafter(1.0, 0.0), 1403715273262142976.0})
    for (double s : {1.0, -1.0}) EXPECT_TRUE(Check(s * v));
  for (int e = -1074; e <= 1023; ++e) ASSERT_TRUE(Check(std::ldexp(1.0, e))) << e;
  for (std::uint64_t t = 1; t < 20000; ++t) {  // the smallest subnormals
    double v;
    std::memcpy(&v, &t, sizeof v);
    ASSERT_TRUE(Check(v)) << t;
  }
  for (int e = -323; e <= 308; ++e) {  // powers of ten
    const std::string t = "1e" + std::to_string(e);
    double v = 0;
    std::from_chars(t.data(), t.data() + t.size(), v);
    ASSERT_TRUE(Check(v)) << t;
  }
}

TEST(NumberFormat, RandomDoublesOverTheWholeRange) {
  std::mt19937_64 rng(20240611);
  std::normal_distribution<double> n;
  for (int i = 0; i < 1000000; ++i) {
    std::uint64_t bits = rng();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isfinite(v)) continue;
    ASSERT_TRUE(Check(v));
  }
  for (int i = 0; i < 1000000; ++i) ASSERT_TRUE(Check(n(rng) * std::pow(10.0, static_cast<int>(n(rng) * 6))));
  for (int i = 0; i < 200000; ++i) ASSERT_TRUE(Check(static_cast<double>(rng() % 10000000) / 1000.0));
}

}  // namespace
