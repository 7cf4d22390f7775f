#include "imuconv/report/anchored_scale.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "imuconv/report/markup.h"

namespace imuconv::report {
namespace {

Rgb Lerp(const Rgb& a, const Rgb& b, double f) {
  f = std::clamp(f, 0.0, 1.0);
  auto mix = [f](unsigned char x, unsigned char y) {
    return static_cast<unsigned char>(std::lround(x + (static_cast<double>(y) - x) * f));
  };
  return {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)};
}

// The calm ramp, within the tolerance: ColorBrewer-like pale grey-blue to a medium blue, light
// enough that black text and the failure colours stand out against it.
constexpr Rgb kCalmLow{0xf2, 0xf5, 0xf8}, kCalmHigh{0x6b, 0x9b, 0xc8};
// The failure ramp, beyond the tolerance: orange to dark red.
constexpr Rgb kFailLow{0xfd, 0x8d, 0x3c}, kFailHigh{0x7f, 0x00, 0x00};
// Signed: below -tolerance, purple to dark violet (overestimated), a calm pale orange for small
// positive values, so the sign reads in the calm part too.
constexpr Rgb kCalmNeg{0xa6, 0xbd, 0xdb}, kCalmMid{0xf7, 0xf7, 0xf7}, kCalmPos{0xfd, 0xdb, 0xc7};
constexpr Rgb kFailNegLow{0x80, 0x73, 0xac}, kFailNegHigh{0x2d, 0x00, 0x4b};

}  // namespace

AnchoredScale AnchoredScale::Magnitude(double min, double max, double tolerance) {
  if (!(min > 0.0 && min < tolerance && tolerance < max && std::isfinite(max)))
    throw std::invalid_argument("an anchored magnitude scale needs 0 < min < tolerance < max");
  return AnchoredScale(Kind::magnitude, min, max, tolerance);
}

AnchoredScale AnchoredScale::Signed(double max, double tolerance) {
  if (!(tolerance > 0.0 && tolerance < max && std::isfinite(max)))
    throw std::invalid_argument("an anchored signed scale needs 0 < tolerance < max");
  return AnchoredScale(Kind::signed_linear, -max, max, tolerance);
}

double AnchoredScale::Position(double v) const {
  if (kind_ == Kind::signed_linear) return std::clamp((v - min_) / (max_ - min_), 0.0, 1.0);
  if (!(v > 0.0)) return 0.0;
  return std::clamp((std::log10(v) - std::log10(min_)) / (std::log10(max_) - std::log10(min_)), 0.0,
                    1.0);
}

bool AnchoredScale::Clamped(double v) const {
  if (kind_ == Kind::magnitude && v == 0.0) return false;  // exact agreement, drawn as itself
  return v < min_ || v > max_;
}

bool AnchoredScale::WithinTolerance(double v) const {
  return kind_ == Kind::magnitude ? (v >= 0.0 && v <= tolerance_) : std::abs(v) <= tolerance_;
}

Rgb AnchoredScale::ColorAt(double t) const {
  t = std::clamp(t, 0.0, 1.0);
  if (kind_ == Kind::magnitude) {
    const double tt = Position(tolerance_);
    return t <= tt ? Lerp(kCalmLow, kCalmHigh, t / tt)
                   : Lerp(kFailLow, kFailHigh, (t - tt) / (1.0 - tt));
  }
  const double v = min_ + t * (max_ - min_);
  if (v > tolerance_) return Lerp(kFailLow, kFailHigh, (v - tolerance_) / (max_ - tolerance_));
  if (v < -tolerance_)
    return Lerp(kFailNegLow, kFailNegHigh, (-v - tolerance_) / (max_ - tolerance_));
  return v >= 0.0 ? Lerp(kCalmMid, kCalmPos, v / tolerance_)
                  : Lerp(kCalmMid, kCalmNeg, -v / tolerance_);
}

Rgb AnchoredScale::Color(double v) const {
  const EntryKind k = Classify(v);
  if (k == EntryKind::not_a_number || k == EntryKind::infinite) return SpecialColor(k);
  if (kind_ == Kind::magnitude) {
    if (k == EntryKind::negative) return SpecialColor(k);
    if (k == EntryKind::zero) return ColorAt(0.0);
  }
  return ColorAt(Position(v));
}

std::vector<std::pair<double, std::string>> AnchoredScale::Ticks() const {
  std::vector<std::pair<double, std::string>> ticks;
  if (kind_ == Kind::magnitude) {
    const int lo = static_cast<int>(std::lround(std::log10(min_))),
              hi = static_cast<int>(std::lround(std::log10(max_)));
    const int step = std::max(1, (hi - lo + 7) / 8);  // at most about nine labels
    for (int k = lo; k <= hi; k += step)
      ticks.push_back({Position(std::pow(10.0, k)), "1e" + std::to_string(k)});
    return ticks;
  }
  for (double v : {min_, min_ / 2.0, 0.0, max_ / 2.0, max_})
    ticks.push_back({Position(v), Readable(v, 3)});
  return ticks;
}

std::vector<double> AnchoredScale::TolerancePositions() const {
  if (kind_ == Kind::magnitude) return {Position(tolerance_)};
  return {Position(-tolerance_), Position(tolerance_)};
}

}  // namespace imuconv::report
