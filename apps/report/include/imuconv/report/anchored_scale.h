// A heatmap colour scale anchored to what the values mean, not fitted to the values: a fixed
// range per kind of matrix and the tolerance the judgment uses, so the same colour means the
// same thing in every report. Values within the tolerance are drawn on a calm ramp (pale
// blue-grey to blue); values beyond it on a ramp that reads as failure (orange to dark red, and
// for signed values below -tolerance, purple to dark violet). Round-off of 1e-16 is then pale
// and a difference of 2 is dark red, where a fitted scale gave both the top colour.
//
// Two kinds:
//  - magnitude: a non-negative value (check's entrywise difference d) on a log axis from `min`
//    to `max`; an exact zero is exact agreement, drawn as the calm end with a dot (so it cannot
//    be taken for a missing cell);
//  - signed: a value on a linear axis from -`max` to `max` (montecarlo's standardized
//    (S - Sigma) / sd), tolerance +-`tolerance`, zero in the middle of the calm part.
// NaN, infinities and (for magnitude) negative values keep color_scale.h's special colours.
#pragma once

#include <string>
#include <vector>

#include "imuconv/report/color_scale.h"

namespace imuconv::report {

class AnchoredScale {
 public:
  enum class Kind { magnitude, signed_linear };

  /// magnitude: 0 < min < tolerance < max; the ends are decades (10^k) for the ticks.
  /// Throws std::invalid_argument otherwise.
  static AnchoredScale Magnitude(double min, double max, double tolerance);
  /// signed: 0 < tolerance < max; the range is [-max, max].
  static AnchoredScale Signed(double max, double tolerance);

  Kind kind() const { return kind_; }
  double min() const { return min_; }  ///< the bottom of the bar (-max for signed)
  double max() const { return max_; }
  double tolerance() const { return tolerance_; }

  /// Where a finite value falls on the bar, 0 (bottom) .. 1 (top), clamped.
  double Position(double v) const;
  /// Whether a finite value is beyond the bar's ends (drawn with the end colour).
  bool Clamped(double v) const;
  /// Whether a value passes: magnitude v <= tolerance (0 included), signed |v| <= tolerance.
  bool WithinTolerance(double v) const;
  /// The colour of a value; NaN, infinite and (magnitude) negative values get SpecialColor.
  Rgb Color(double v) const;
  /// The colour at a bar position t in [0, 1] (the legend's bar).
  Rgb ColorAt(double t) const;
  /// Tick positions and labels for the legend's bar, the tolerance's own excluded.
  std::vector<std::pair<double, std::string>> Ticks() const;
  /// The tolerance's position(s) on the bar: one for magnitude, two (+-) for signed.
  std::vector<double> TolerancePositions() const;

 private:
  AnchoredScale(Kind kind, double min, double max, double tolerance)
      : kind_(kind), min_(min), max_(max), tolerance_(tolerance) {}
  Kind kind_;
  double min_, max_, tolerance_;
};

}  // namespace imuconv::report
