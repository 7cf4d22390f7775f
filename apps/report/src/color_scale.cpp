#include "imuconv/report/color_scale.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace imuconv::report {
namespace {

// Ten evenly spaced samples of matplotlib's viridis (van der Walt and Smith, 2015), t = k / 9.
constexpr std::array<Rgb, 10> kViridis = {{{0x44, 0x01, 0x54},
                                           {0x48, 0x28, 0x78},
                                           {0x3e, 0x49, 0x89},
                                           {0x31, 0x68, 0x8e},
                                           {0x26, 0x82, 0x8e},
                                           {0x1f, 0x9e, 0x89},
                                           {0x35, 0xb7, 0x79},
                                           {0x6e, 0xce, 0x58},
                                           {0xb5, 0xde, 0x2b},
                                           {0xfd, 0xe7, 0x25}}};

unsigned char Mix(unsigned char a, unsigned char b, double f) {
  return static_cast<unsigned char>(std::lround(a + (static_cast<double>(b) - a) * f));
}

}  // namespace

std::string Rgb::Hex() const {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", r, g, b);
  return buf;
}

Rgb Viridis(double t) {
  if (!(t > 0.0)) return kViridis.front();  // also NaN
  if (t >= 1.0) return kViridis.back();
  const double x = t * (kViridis.size() - 1);
  const std::size_t k = static_cast<std::size_t>(x);
  const double f = x - static_cast<double>(k);
  const Rgb& a = kViridis[k];
  const Rgb& b = kViridis[k + 1];
  return {Mix(a.r, b.r, f), Mix(a.g, b.g, f), Mix(a.b, b.b, f)};
}

EntryKind Classify(double v) {
  if (std::isnan(v)) return EntryKind::not_a_number;
  if (std::isinf(v)) return EntryKind::infinite;
  if (v == 0.0) return EntryKind::zero;
  if (v < 0.0) return EntryKind::negative;
  return EntryKind::value;
}

Rgb SpecialColor(EntryKind kind) {
  switch (kind) {
    case EntryKind::zero:
      return {0xff, 0xff, 0xff};
    case EntryKind::not_a_number:
      return {0xff, 0x00, 0xff};
    case EntryKind::infinite:
      return {0xd6, 0x27, 0x28};
    case EntryKind::negative:
      return {0x80, 0x80, 0x80};
    case EntryKind::value:
      break;
  }
  return {0, 0, 0};
}

const char* KindName(EntryKind kind) {
  switch (kind) {
    case EntryKind::zero:
      return "0";
    case EntryKind::not_a_number:
      return "NaN";
    case EntryKind::infinite:
      return "inf";
    case EntryKind::negative:
      return "negative";
    case EntryKind::value:
      return "value";
  }
  return "";
}

LogColorScale::LogColorScale(int lo_decade, int hi_decade) : lo_(lo_decade), hi_(hi_decade) {
  if (!(lo_ < hi_)) throw std::invalid_argument("a log colour scale needs lo_decade < hi_decade");
}

LogColorScale LogColorScale::Fit(const std::vector<double>& values, int max_decades) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (double v : values)
    if (Classify(v) == EntryKind::value) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (!(hi > 0.0)) return LogColorScale(-1, 0);
  // A value that is a power of ten is a decade's end either way: at worst (log10 rounding
  // just past the integer) the scale is one decade wider than needed, never narrower.
  int lo_d = static_cast<int>(std::floor(std::log10(lo)));
  int hi_d = static_cast<int>(std::ceil(std::log10(hi)));
  if (hi_d <= lo_d) hi_d = lo_d + 1;
  if (max_decades < 1) max_decades = 1;
  if (hi_d - lo_d > max_decades) lo_d = hi_d - max_decades;
  return LogColorScale(lo_d, hi_d);
}

double LogColorScale::Position(double v) const {
  const double t = (std::log10(v) - lo_) / static_cast<double>(hi_ - lo_);
  return std::clamp(t, 0.0, 1.0);
}

bool LogColorScale::Clamped(double v) const {
  const double l = std::log10(v);
  return l < lo_ || l > hi_;
}

Rgb LogColorScale::Color(double v) const {
  const EntryKind k = Classify(v);
  return k == EntryKind::value ? Viridis(Position(v)) : SpecialColor(k);
}

}  // namespace imuconv::report
