// The digits come from std::to_chars (shortest round trip, the closest of the shortest forms,
// ties to even); this file only lays them out the way nlohmann::json does, so that an output
// written here reads the same as one dumped by nlohmann (and as the outputs of earlier
// versions, which tests/pipeline/number_format.cpp pins down). to_chars' scientific form is
// rearranged in place: the exponent form is already nlohmann's, the fixed forms move at most
// 17 digits.
#include "number_format.h"

#include <charconv>
#include <cstring>

namespace imuconv::pipeline {

char* FormatShortest(char* p, double v) {
  // [-]d[.ddd]e(+|-)XX[X]: at most 24 characters, 17 digits.
  char* const end = std::to_chars(p, p + kMaxDoubleChars, v, std::chars_format::scientific).ptr;
  if (*p == '-') ++p;
  if (*p == '0') {  // zero ("0e+00")
    std::memcpy(p, "0.0", 3);
    return p + 3;
  }
  char* e = p + 1;
  while (*e != 'e') ++e;
  const int k = e == p + 1 ? 1 : static_cast<int>(e - p) - 1;  // significant digits
  int exp10 = 0;
  for (const char* q = e + 2; q < end; ++q) exp10 = 10 * exp10 + (*q - '0');
  if (e[1] == '-') exp10 = -exp10;
  // v = 0.d1d2...dk 10^n. nlohmann's layout: fixed notation for -4 < n <= 15, otherwise the
  // exponent form, which is to_chars' own (a sign and at least two exponent digits).
  const int n = exp10 + 1;
  if (0 < n && n <= 15) {
    // Drop the point after the first digit: the digits then sit at p[0..k).
    if (k > 1) std::memmove(p + 1, p + 2, static_cast<std::size_t>(k - 1));
    if (k <= n) {  // digits[000].0: integral values stay floating point
      std::memset(p + k, '0', static_cast<std::size_t>(n - k));
      std::memcpy(p + n, ".0", 2);
      return p + n + 2;
    }
    std::memmove(p + n + 1, p + n, static_cast<std::size_t>(k - n));  // dig.its
    p[n] = '.';
    return p + k + 1;
  }
  if (-4 < n && n <= 0) {  // 0.[000]digits
    char digits[17];
    digits[0] = p[0];
    if (k > 1) std::memcpy(digits + 1, p + 2, static_cast<std::size_t>(k - 1));
    std::memcpy(p, "0.000", static_cast<std::size_t>(2 - n));
    std::memcpy(p + 2 - n, digits, static_cast<std::size_t>(k));
    return p + 2 - n + k;
  }
  return end;
}

}  // namespace imuconv::pipeline
