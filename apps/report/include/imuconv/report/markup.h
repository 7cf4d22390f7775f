// Text and numbers as they go into the report's HTML and SVG: every string that came from
// outside (a file name, a convention id, a label) passes through EscapeText before it is
// written, so a name like `<b>&"x'` shows as those characters and can neither close an
// element nor an attribute. The report is written as well-formed XML (XHTML syntax, served as
// HTML), so the same five entities serve both.
#pragma once

#include <string>
#include <string_view>

namespace imuconv::report {

/// `&`, `<`, `>`, `"` and `'` as entities; a control character other than tab and newline
/// (not allowed in XML 1.0) and an invalid UTF-8 byte as U+FFFD, so the document stays
/// well-formed whatever bytes a file name holds.
std::string EscapeText(std::string_view text);

/// A coordinate or length for an SVG attribute: fixed point with two decimals, no exponent
/// ("12.5", "-3", "0"); a non-finite value is written as 0 (our layout never makes one).
std::string Coordinate(double v);

/// A value for a person to read: `%.*g` with `digits` significant digits; "NaN", "inf", "-inf".
std::string Readable(double v, int digits = 3);

}  // namespace imuconv::report
