// Shortest round-trip formatting of doubles for JSON output (internal to imuconv_pipeline).
#pragma once

namespace imuconv::pipeline {

/// Longest text FormatShortest writes: "-1.2345678901234567e-308".
constexpr int kMaxDoubleChars = 25;

/// Writes a finite double at p in the shortest decimal form that reads back to the same
/// double (of the shortest forms, the one closest to it: std::to_chars' digits), laid out as
/// nlohmann::json does: "1.0", "0.25", "123.5", "0.0001", "1e-05", "1.5e+20", "-0.0".
/// Returns the end; at most kMaxDoubleChars are written. v must be finite.
char* FormatShortest(char* p, double v);

}  // namespace imuconv::pipeline
