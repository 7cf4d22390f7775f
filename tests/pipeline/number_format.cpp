// Output numbers: the JSON writer's shortest double formatting. Checked by the properties it
// promises, not against the std::to_chars it is built on (that would assert nothing):
//   - the text reads back to the same double;
//   - no decimal with fewer significant digits reads back to it (shortest);
//   - of the decimals with as many digits, it is the one closest to the double (the correctly
//     rounded one, from glibc's exact printf);
//   - nlohmann::json's layout: fixed notation for 1e-5 <= |v| < 1e15 (integral values with
//     ".0"), the exponent form with a sign and at least two exponent digits otherwise.
// Over the whole range: random bit patterns, subnormals, powers of two and of ten, integers
// near 2^53, decimals.
#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "../../apps/pipeline/src/io/number_format.h"
#include "imuconv/pipeline/json_writer.h"

namespace {
using imuconv::pipeline::FormatShortest;
using imuconv::pipeline::kMaxDoubleChars;

std::string Format(double v) {
  char buf[64];
  return std::string(buf, FormatShortest(buf, v));
}

// The significant digits d1d2...dk (no leading or trailing zeros) and the exponent n with
// |value| = 0.d1d2...dk 10^n, of a number in any of the forms.
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

bool ReadsBackTo(const std::string& s, double v) {
  double back = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), back);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() &&
         std::memcmp(&back, &v, sizeof v) == 0;
}

// |v| correctly rounded to `digits` significant digits, "d.ddde+X" (glibc's printf is exact).
std::string Rounded(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*e", digits - 1, std::abs(v));
  return buf;
}

// The (digits)-digit decimal one unit in the last place above or below `rounded` (its
// neighbours: with the rounded one, they include the two (digits)-digit decimals around v).
std::string Neighbour(const std::string& rounded, int step) {
  const Digits d = Parse(rounded);
  std::string m = rounded.substr(0, rounded.find('e'));
  m.erase(std::remove(m.begin(), m.end(), '.'), m.end());
  unsigned long long n = std::stoull(m);
  if (step < 0 && n == 0) return rounded;
  n = step > 0 ? n + 1 : n - 1;
  return std::to_string(n) + "e" + std::to_string(d.exp10 - static_cast<int>(m.size()));
}

// The layout rules: which form the exponent n (v = 0.d1d2... 10^n) and digit count k ask for.
::testing::AssertionResult LaidOut(const std::string& s, const Digits& d) {
  const std::string body = s[0] == '-' ? s.substr(1) : s;
  const int k = static_cast<int>(d.d.size()), n = d.exp10;
  const bool exp_form = body.find('e') != std::string::npos;
  if (exp_form != !(-4 < n && n <= 15))
    return ::testing::AssertionFailure() << s << ": wrong notation for 0.d 10^" << n;
  if (exp_form) {
    const std::size_t e = body.find('e');
    const std::string mant = body.substr(0, e), ex = body.substr(e + 1);
    const bool mant_ok = k == 1
                             ? mant.size() == 1
                             : (mant.size() == static_cast<std::size_t>(k + 1) && mant[1] == '.');
    const bool ex_ok =
        ex.size() >= 3 && (ex[0] == '+' || ex[0] == '-') && (ex.size() == 3 || ex[1] != '0');
    if (!mant_ok || !ex_ok) return ::testing::AssertionFailure() << s << ": not d[.ddd]e(+|-)XX";
    return ::testing::AssertionSuccess();
  }
  const std::size_t dot = body.find('.');
  if (dot == std::string::npos || dot + 1 == body.size())
    return ::testing::AssertionFailure() << s << ": no digit after the point";
  if (k <= n && body.substr(dot) != ".0")
    return ::testing::AssertionFailure() << s << ": an integral value must end in .0";
  if (k > n && body.back() == '0') return ::testing::AssertionFailure() << s << ": trailing zero";
  if (n <= 0 && body.substr(0, 2) != "0.")
    return ::testing::AssertionFailure() << s << ": expected 0.[000]digits";
  return ::testing::AssertionSuccess();
}

// Every property; the failure message names v.
::testing::AssertionResult Check(double v) {
  const std::string s = Format(v);
  if (s.size() > static_cast<std::size_t>(kMaxDoubleChars))
    return ::testing::AssertionFailure() << s << " is too long";
  if (!ReadsBackTo(s, v))
    return ::testing::AssertionFailure() << s << " does not read back to " << std::hexfloat << v;
  if (std::signbit(v) != (s[0] == '-')) return ::testing::AssertionFailure() << s << ": wrong sign";
  if (v == 0.0)
    return s == (std::signbit(v) ? "-0.0" : "0.0") ? ::testing::AssertionSuccess()
                                                   : ::testing::AssertionFailure() << s;
  const Digits d = Parse(s);
  const int k = static_cast<int>(d.d.size());
  const std::string sign = v < 0 ? "-" : "";
  // Closest: the correctly rounded k-digit decimal if it reads back. At a power of two the
  // rounding interval is narrower below v, and the nearest decimal can fall outside it; then
  // the nearest one on the other side of v, a neighbour of the rounded one.
  const std::string rk = Rounded(v, k);
  if (ReadsBackTo(sign + rk, v) ? !(Parse(rk) == d)
                                : !(Parse(Neighbour(rk, -1)) == d || Parse(Neighbour(rk, +1)) == d))
    return ::testing::AssertionFailure()
           << s << " is not the closest k-digit decimal that reads back (" << rk << ")";
  // Shortest: none of the (k-1)-digit decimals around v reads back (shorter ones are among
  // them, with trailing zeros).
  if (k > 1) {
    const std::string r = Rounded(v, k - 1);
    for (const std::string& c : {r, Neighbour(r, -1), Neighbour(r, +1)})
      if (ReadsBackTo(sign + c, v))
        return ::testing::AssertionFailure() << s << " is not the shortest: " << c << " reads back";
  }
  return LaidOut(s, d);
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
  EXPECT_EQ(Format(-0.00012), "-0.00012");
  EXPECT_EQ(Format(1e-05), "1e-05");
  EXPECT_EQ(Format(1.5e-07), "1.5e-07");
  EXPECT_EQ(Format(1e15), "1e+15");
  EXPECT_EQ(Format(1e100), "1e+100");
  EXPECT_EQ(Format(100.0), "100.0");
  EXPECT_EQ(Format(123456789012345.0), "123456789012345.0");
  EXPECT_EQ(Format(1234567890123456.0), "1.234567890123456e+15");
  EXPECT_EQ(Format(9007199254740993.0), "9.007199254740992e+15");
  EXPECT_EQ(Format(1.5e20), "1.5e+20");
  EXPECT_EQ(Format(1.7976931348623157e308), "1.7976931348623157e+308");
  EXPECT_EQ(Format(-2.2250738585072014e-308), "-2.2250738585072014e-308");
  EXPECT_EQ(Format(5e-324), "5e-324");
  EXPECT_EQ(Format(1e-323), "1e-323");
  EXPECT_EQ(Format(8e-323), "8e-323");  // not 7.9e-323: one digit is enough
  EXPECT_EQ(Format(-9.81), "-9.81");
  EXPECT_EQ(Format(145.595000064), "145.595000064");
  EXPECT_EQ(Format(0.30000000000000004), "0.30000000000000004");
  // The writer uses it for every number.
  std::string out;
  imuconv::pipeline::JsonWriter w(out);
  const double xs[] = {0.0, -0.0, 1.0, 0.1, 1e-05};
  w.numbers(xs, 5);
  EXPECT_EQ(out, "[0.0, -0.0, 1.0, 0.1, 1e-05]");
}

TEST(NumberFormat, TheChecksCanFail) {
  // The property checks reject a longer, a farther or a badly laid-out text.
  const Digits third = Parse("3.3333333333333331e-01");
  EXPECT_FALSE(LaidOut("3.3333333333333331e-01", third));  // fixed notation expected
  EXPECT_FALSE(LaidOut("100", Parse("100")));
  EXPECT_FALSE(LaidOut("1e+5", Parse("1e+5")));
  EXPECT_FALSE(LaidOut("1.0e+20", Parse("1.0e+20")));
  EXPECT_TRUE(ReadsBackTo("0.10000000000000001", 0.1));  // reads back, but 0.1 is shorter:
  EXPECT_TRUE(ReadsBackTo(Rounded(0.1, 1), 0.1));
  EXPECT_EQ(Neighbour("1.5e+00", 1), "16e-1");
  EXPECT_EQ(Neighbour("1.5e+00", -1), "14e-1");
}

TEST(NumberFormat, EdgeCases) {
  const double lim_max = std::numeric_limits<double>::max(),
               lim_min = std::numeric_limits<double>::min(),
               denorm = std::numeric_limits<double>::denorm_min();
  for (double v : {0.0,
                   lim_max,
                   lim_min,
                   denorm,
                   2 * denorm,
                   3 * denorm,
                   16 * denorm,
                   std::nextafter(lim_min, 0.0),
                   9007199254740991.0,
                   9007199254740992.0,
                   9007199254740993.0,
                   1e22,
                   1e23,
                   5e-324,
                   0.3,
                   2.2250738585072009e-308,
                   std::nextafter(1.0, 2.0),
                   std::nextafter(1.0, 0.0),
                   1403715273262142976.0,
                   1e-5,
                   std::nextafter(1e-5, 0.0),
                   1e15,
                   std::nextafter(1e15, 0.0),
                   1e-4,
                   std::nextafter(1e-4, 0.0)})
    for (double s : {1.0, -1.0}) EXPECT_TRUE(Check(s * v));
  for (int e = -1074; e <= 1023; ++e) {  // powers of two and their neighbours
    const double v = std::ldexp(1.0, e);
    ASSERT_TRUE(Check(v)) << e;
    ASSERT_TRUE(Check(std::nextafter(v, 0.0))) << e;
    ASSERT_TRUE(Check(std::nextafter(v, 2 * v + 1))) << e;
  }
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
  for (std::int64_t d = -20000; d <= 20000; ++d)
    ASSERT_TRUE(Check(static_cast<double>((std::int64_t{1} << 53) + d))) << d;
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
  for (int i = 0; i < 1000000; ++i)
    ASSERT_TRUE(Check(n(rng) * std::pow(10.0, static_cast<int>(n(rng) * 6))));
  for (int i = 0; i < 200000; ++i)
    ASSERT_TRUE(Check(static_cast<double>(rng() % 10000000) / 1000.0));
}

}  // namespace
