// Schubfach (R. Giulietti, "The Schubfach way to render doubles", 2020; the algorithm of
// Java's Double.toString since JDK 19), written for imuconv's JSON output. tests/pipeline/
// number_format.cpp checks it against std::to_chars (same digits) and std::from_chars
// (round trip) on millions of doubles over the whole range.
#include "double_format.h"

#include <cstdint>
#include <cstring>

namespace imuconv::pipeline {
namespace {

using u64 = std::uint64_t;
using u128 = unsigned __int128;

constexpr int kQMin = -1074;  // 2^kQMin: the smallest subnormal
constexpr u64 kCMin = u64{1} << 52;
constexpr u64 kCTiny = 3;  // subnormal significands below this: special-cased
constexpr int kKMin = -324;
constexpr u64 kMask63 = (u64{1} << 63) - 1;

struct G {
  u64 g1, g0;
};
constexpr G kG[] = {
#include "pow10_table.inc"
};
static_assert(sizeof kG / sizeof kG[0] == 617, "k = -324 .. 292");

// floor(e log10 2), floor(log10(3/4 2^e)), floor(e log2 10), exact for the exponents used.
inline int FloorLog10Pow2(int e) { return static_cast<int>((static_cast<std::int64_t>(e) * 661971961083LL) >> 41); }
inline int FloorLog10ThreeQuartersPow2(int e) {
  return static_cast<int>((static_cast<std::int64_t>(e) * 661971961083LL - 274743187321LL) >> 41);
}
inline int FloorLog2Pow10(int e) { return static_cast<int>((static_cast<std::int64_t>(e) * 913124641741LL) >> 38); }

inline u64 MulHigh(u64 a, u64 b) { return static_cast<u64>((static_cast<u128>(a) * b) >> 64); }

// Round to odd of g cp / 2^127.
inline u64 Rop(u64 g1, u64 g0, u64 cp) {
  const u64 x1 = MulHigh(g0, cp);
  const u64 y0 = g1 * cp;
  const u64 y1 = MulHigh(g1, cp);
  const u64 z = (y0 >> 1) + x1;
  const u64 vbp = y1 + (z >> 63);
  return vbp | (((z & kMask63) + kMask63) >> 63);
}

struct Decimal {
  u64 f;  // significand
  int e;  // value = f 10^e
};

// v = c 2^q: the shortest decimal in the rounding interval, the closest one of several.
Decimal ToDecimal(int q, u64 c, int dk) {
  const u64 out = c & 1;
  const u64 cb = c << 2;
  const u64 cbr = cb + 2;
  u64 cbl;
  int k;
  if (c != kCMin || q == kQMin) {
    cbl = cb - 2;
    k = FloorLog10Pow2(q);
  } else {
    cbl = cb - 1;
    k = FloorLog10ThreeQuartersPow2(q);
  }
  const int h = q + FloorLog2Pow10(-k) + 2;
  const G& g = kG[k - kKMin];
  const u64 vb = Rop(g.g1, g.g0, cb << h);
  const u64 vbl = Rop(g.g1, g.g0, cbl << h);
  const u64 vbr = Rop(g.g1, g.g0, cbr << h);
  const u64 s = vb >> 2;
  if (s >= 10) {
    // One digit less: s' = floor(s / 10); u' = 10 s', w' = 10 s' + 10. (Schubfach tries this
    // from s >= 100; from 10 on it also finds the one-digit forms of small subnormals, e.g.
    // 8e-323 rather than 7.9e-323. Their rounding interval is narrower than 10 units of s.)
    const u64 sp10 = 10 * (s / 10);
    const u64 tp10 = sp10 + 10;
    const bool upin = vbl + out <= sp10 << 2;
    const bool wpin = (tp10 << 2) + out <= vbr;
    if (upin != wpin) return {upin ? sp10 : tp10, k};
  }
  const u64 t = s + 1;
  const bool uin = vbl + out <= s << 2;
  const bool win = (t << 2) + out <= vbr;
  if (uin != win) return {uin ? s : t, k + dk};
  // Both in the interval: the closer one (ties to even).
  const std::int64_t cmp = static_cast<std::int64_t>(vb - ((s + t) << 1));
  return {(cmp < 0 || (cmp == 0 && (s & 1) == 0)) ? s : t, k + dk};
}

constexpr char kDigits2[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

// Writes the 8 digits of x < 10^8 (leading zeros included) at p.
inline void Write8(char* p, std::uint32_t x) {
  const std::uint32_t hi = x / 10000, lo = x % 10000;
  std::memcpy(p, kDigits2 + 2 * (hi / 100), 2);
  std::memcpy(p + 2, kDigits2 + 2 * (hi % 100), 2);
  std::memcpy(p + 4, kDigits2 + 2 * (lo / 100), 2);
  std::memcpy(p + 6, kDigits2 + 2 * (lo % 100), 2);
}

// Writes the decimal digits of f (0 < f < 10^17) ending just before `end`; returns their
// start. Two independent 8-digit halves in 32-bit arithmetic.
inline char* DigitsBackward(char* end, u64 f) {
  if (f >= 100000000) {
    const u64 top = f / 100000000;
    Write8(end - 8, static_cast<std::uint32_t>(f - top * 100000000));
    end -= 8;
    f = top;
    if (f >= 100000000) {
      const u64 top2 = f / 100000000;
      Write8(end - 8, static_cast<std::uint32_t>(f - top2 * 100000000));
      end -= 8;
      f = top2;
    }
  }
  auto x = static_cast<std::uint32_t>(f);
  while (x >= 100) {
    const std::uint32_t r = x % 100;
    x /= 100;
    end -= 2;
    std::memcpy(end, kDigits2 + 2 * r, 2);
  }
  if (x >= 10) {
    end -= 2;
    std::memcpy(end, kDigits2 + 2 * x, 2);
  } else {
    *--end = static_cast<char>('0' + x);
  }
  return end;
}

// Decimal digits of f (0 < f < 10^17).
inline int DigitCount(u64 f) {
  static constexpr u64 kPow10[] = {1ULL, 10ULL, 100ULL, 1000ULL, 10000ULL, 100000ULL, 1000000ULL, 10000000ULL,
                                   100000000ULL, 1000000000ULL, 10000000000ULL, 100000000000ULL, 1000000000000ULL,
                                   10000000000000ULL, 100000000000000ULL, 1000000000000000ULL, 10000000000000000ULL,
                                   100000000000000000ULL, 1000000000000000000ULL};
  const int bits = 64 - __builtin_clzll(f);
  const int len = FloorLog10Pow2(bits);  // 10^len <= 2^bits
  return f >= kPow10[len] ? len + 1 : len;
}

char* AppendExponent(char* p, int e) {
  if (e < 0) {
    e = -e;
    *p++ = '-';
  } else {
    *p++ = '+';
  }
  if (e < 10) {
    *p++ = '0';
    *p++ = static_cast<char>('0' + e);
  } else if (e < 100) {
    std::memcpy(p, kDigits2 + 2 * e, 2);
    p += 2;
  } else {
    *p++ = static_cast<char>('0' + e / 100);
    std::memcpy(p, kDigits2 + 2 * (e % 100), 2);
    p += 2;
  }
  return p;
}

}  // namespace

char* FormatShortest(char* p, double v) {
  u64 bits;
  std::memcpy(&bits, &v, sizeof bits);
  if (bits >> 63) *p++ = '-';
  const u64 t = bits & ((u64{1} << 52) - 1);
  const int bq = static_cast<int>((bits >> 52) & 0x7ff);
  Decimal d;
  if (bq != 0) {
    const int mq = -kQMin + 1 - bq;  // -q
    const u64 c = kCMin | t;
    if (0 < mq && mq < 53 && ((c >> mq) << mq) == c) {
      d = {c >> mq, 0};  // an integer
    } else {
      d = ToDecimal(-mq, c, 0);
    }
  } else if (t >= kCTiny) {
    d = ToDecimal(kQMin, t, 0);
  } else if (t != 0) {
    // 4.9e-324 and 9.9e-324 (two digits from Schubfach's scaling by 10): one digit is enough.
    d = t == 1 ? Decimal{5, -324} : Decimal{1, -323};
  } else {
    std::memcpy(p, "0.0", 3);
    return p + 3;
  }
  while (d.f % 10 == 0) {  // f > 0 here
    d.f /= 10;
    ++d.e;
  }
  // nlohmann::json's layout (min exponent -4, max 15) for v = digits 10^(n - k); the digits
  // are written in place.
  const int k = DigitCount(d.f);
  const int n = k + d.e;
  if (k <= n && n <= 15) {  // digits[000].0
    DigitsBackward(p + k, d.f);
    p += k;
    std::memset(p, '0', static_cast<std::size_t>(n - k));
    p += n - k;
    *p++ = '.';
    *p++ = '0';
    return p;
  }
  if (0 < n && n <= 15) {  // dig.its: the digits one place to the right, then the point
    DigitsBackward(p + 1 + k, d.f);
    for (int i = 0; i < n; ++i) p[i] = p[i + 1];
    p[n] = '.';
    return p + k + 1;
  }
  if (-4 < n && n <= 0) {  // 0.[000]digits
    std::memcpy(p, "0.0000", 6);  // "0." and up to 4 zeros, as many as needed kept
    p += 2 - n;
    DigitsBackward(p + k, d.f);
    return p + k;
  }
  // d[.igits]e+XX: the digits one place to the right, then the first one moved before the point
  DigitsBackward(p + 1 + k, d.f);
  p[0] = p[1];
  if (k > 1) {
    p[1] = '.';
    p += k + 1;
  } else {
    p += 1;
  }
  *p++ = 'e';
  return AppendExponent(p, n - 1);
}

}  // namespace imuconv::pipeline
