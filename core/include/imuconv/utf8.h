// Well-formed UTF-8 (RFC 3629): what JSON text may hold (printable.h keeps the same sequences).
//
// Names and versions reach imuconv's JSON outputs from hostile places (a pipeline's path, a
// plugin's version string); JSON text is UTF-8, so a byte sequence that is not is refused where
// it is written or read, never copied raw into a document that then is not JSON.
#pragma once

#include <cstddef>
#include <string_view>

namespace imuconv {

/// The length (1 to 4) of the well-formed UTF-8 sequence starting at s[i], or 0 when the bytes
/// there are not one: a stray continuation byte, a truncated sequence, an overlong form
/// (C0, C1, E0 80..9F, F0 80..8F), a surrogate (ED A0..BF) or a code point above U+10FFFF.
inline std::size_t Utf8SequenceLength(std::string_view s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  if (c < 0x80) return 1;
  std::size_t len = 0;
  if (c >= 0xc2 && c <= 0xdf)
    len = 2;
  else if (c >= 0xe0 && c <= 0xef)
    len = 3;
  else if (c >= 0xf0 && c <= 0xf4)
    len = 4;
  if (len == 0 || i + len > s.size()) return 0;
  for (std::size_t k = 1; k < len; ++k)
    if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return 0;
  const auto c1 = static_cast<unsigned char>(s[i + 1]);
  if (c == 0xe0 && c1 < 0xa0) return 0;   // overlong
  if (c == 0xed && c1 >= 0xa0) return 0;  // surrogate
  if (c == 0xf0 && c1 < 0x90) return 0;   // overlong
  if (c == 0xf4 && c1 >= 0x90) return 0;  // above U+10FFFF
  return len;
}

/// The offset of the first byte of `s` that is not part of well-formed UTF-8, or
/// std::string_view::npos when all of it is.
inline std::size_t FirstInvalidUtf8(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t len = Utf8SequenceLength(s, i);
    if (len == 0) return i;
    i += len;
  }
  return std::string_view::npos;
}

}  // namespace imuconv
