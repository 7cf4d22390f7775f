// The heatmaps' colour scale: a value's decade (log10) mapped linearly onto the viridis colour
// map, which is perceptually uniform and readable in grey and by the colour-blind, so equal
// steps in colour are equal ratios of the value. The entries a log scale cannot place get
// colours of their own that no value has: an exact zero (white), NaN (magenta), an infinity
// (red) and a negative value (grey).
#pragma once

#include <string>
#include <vector>

namespace imuconv::report {

struct Rgb {
  unsigned char r = 0, g = 0, b = 0;
  /// "#rrggbb".
  std::string Hex() const;
  bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
};

/// The viridis colour map at t in [0, 1] (clamped): linear in sRGB between ten samples of the
/// map taken at t = 0, 1/9, ..., 1 (#440154 ... #fde725).
Rgb Viridis(double t);

enum class EntryKind { value, zero, not_a_number, infinite, negative };

/// value: positive and finite; zero: +0 or -0; infinite: either sign.
EntryKind Classify(double v);

/// The colour an entry of `kind` other than `value` is drawn with.
Rgb SpecialColor(EntryKind kind);

/// "0", "NaN", "inf", "negative": what the legend calls each special kind.
const char* KindName(EntryKind kind);

class LogColorScale {
 public:
  /// Values from 10^lo_decade (bottom colour) to 10^hi_decade (top colour). Throws
  /// std::invalid_argument unless lo_decade < hi_decade.
  LogColorScale(int lo_decade, int hi_decade);

  /// The decades the positive finite `values` span (floor of the smallest's log10, ceiling of
  /// the largest's; at least one decade), at most `max_decades` wide: beyond that the smallest
  /// values share the bottom colour (the large differences are the ones a reader looks for).
  /// With no positive finite value: [-1, 0].
  static LogColorScale Fit(const std::vector<double>& values, int max_decades = 16);

  int lo_decade() const { return lo_; }
  int hi_decade() const { return hi_; }

  /// Where a positive finite value falls: 0 at 10^lo, 1 at 10^hi, clamped to [0, 1].
  double Position(double v) const;
  /// Whether a positive finite value lies outside [10^lo, 10^hi] (it is drawn with the end colour).
  bool Clamped(double v) const;
  /// The value's colour: Viridis(Position(v)) for a value, SpecialColor(kind) for the others.
  Rgb Color(double v) const;

 private:
  int lo_, hi_;
};

}  // namespace imuconv::report
