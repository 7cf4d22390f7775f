// Printable(s): text from a file, a plugin or a command line, made safe to put in a message.
//
// Ids, keys and paths come from hostile input. Written raw, a NUL cuts a message short, a
// newline can fake a line of output ("ok") and an escape sequence can rewrite the terminal.
// Printable keeps printable ASCII and well-formed UTF-8 as they are and writes every other
// byte as an escape: \n, \r, \t, \0 and \xNN (a backslash itself as \\).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace imuconv {

inline std::string Printable(std::string_view s) {
  static const char* kHex = "0123456789abcdef";
  std::string out;
  out.reserve(s.size());
  const auto escape = [&](unsigned char c) {
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 15];
  };
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      if (c == '\\') out += '\\';
      out += static_cast<char>(c);
      ++i;
      continue;
    }
    switch (c) {
      case '\n':
        out += "\\n";
        ++i;
        continue;
      case '\r':
        out += "\\r";
        ++i;
        continue;
      case '\t':
        out += "\\t";
        ++i;
        continue;
      case '\0':
        out += "\\0";
        ++i;
        continue;
      default:
        break;
    }
    // A well-formed UTF-8 sequence (no overlong forms, no surrogates, at most U+10FFFF) is
    // kept; C1 control characters (U+0080..U+009F) are escaped like C0 ones.
    std::size_t len = 0;
    if (c >= 0xc2 && c <= 0xdf)
      len = 2;
    else if (c >= 0xe0 && c <= 0xef)
      len = 3;
    else if (c >= 0xf0 && c <= 0xf4)
      len = 4;
    bool ok = len > 0 && i + len <= s.size();
    for (std::size_t k = 1; ok && k < len; ++k)
      ok = (static_cast<unsigned char>(s[i + k]) & 0xc0) == 0x80;
    if (ok) {
      const auto c1 = static_cast<unsigned char>(s[i + 1]);
      if (c == 0xe0 && c1 < 0xa0) ok = false;   // overlong
      if (c == 0xed && c1 >= 0xa0) ok = false;  // surrogate
      if (c == 0xf0 && c1 < 0x90) ok = false;   // overlong
      if (c == 0xf4 && c1 >= 0x90) ok = false;  // above U+10FFFF
      if (c == 0xc2 && c1 < 0xa0) ok = false;   // C1 control
    }
    if (!ok) {
      escape(c);
      ++i;
      continue;
    }
    out.append(s.substr(i, len));
    i += len;
  }
  return out;
}

/// Printable(s) in single quotes, for names inside a sentence: 'rk4'.
inline std::string Quoted(std::string_view s) { return "'" + Printable(s) + "'"; }

}  // namespace imuconv
