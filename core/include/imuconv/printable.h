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

#include "imuconv/utf8.h"

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
    // A well-formed UTF-8 sequence of two bytes or more (utf8.h: no overlong forms, no
    // surrogates, at most U+10FFFF) is kept; C1 control characters (U+0080..U+009F, C2 80..9F)
    // are escaped like C0 ones, and so is every other byte (a control byte below 0x80 is a
    // sequence of one).
    const std::size_t len = Utf8SequenceLength(s, i);
    const bool c1_control = len == 2 && c == 0xc2 && static_cast<unsigned char>(s[i + 1]) < 0xa0;
    if (len < 2 || c1_control) {
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
