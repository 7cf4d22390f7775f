// Timestamps as written (TimeValue) and relative to an origin (TimeOrigin); see imu_reader.h.
#include <algorithm>
#include <charconv>
#include <cmath>

#include "csv_text.h"
#include "imuconv/pipeline/imu_reader.h"

namespace imuconv::pipeline {

using data::ParseDouble;
using data::Trim;

namespace {

// Normalises whole + frac so that frac is in [0, 1).
TimeValue Normalised(std::int64_t whole, double frac) {
  const double f = std::floor(frac);
  whole += static_cast<std::int64_t>(f);
  frac -= f;
  if (frac >= 1.0) {
    whole += 1;
    frac = 0.0;
  }
  return {whole, frac};
}

}  // namespace

TimeValue TimeValueFromDouble(double t) {
  // Beyond +-9e18 the whole part would not fit int64 (a cast would be undefined): saturate.
  constexpr double kMax = 9.0e18;
  if (!(t <= kMax)) return {static_cast<std::int64_t>(kMax), 0.0};  // also NaN
  if (t < -kMax) return {-static_cast<std::int64_t>(kMax), 0.0};
  const double w = std::floor(t);
  return Normalised(static_cast<std::int64_t>(w), t - w);
}

std::optional<TimeValue> ParseTimeValue(std::string_view text) {
  std::string_view s = Trim(text);
  if (s.empty()) return std::nullopt;
  bool neg = false;
  std::string_view body = s;
  if (body.front() == '+' || body.front() == '-') {
    neg = body.front() == '-';
    body.remove_prefix(1);
  }
  const std::size_t dot = body.find('.');
  const std::string_view int_part = body.substr(0, dot);
  const std::string_view frac_part =
      dot == std::string_view::npos ? std::string_view() : body.substr(dot + 1);
  const auto all_digits = [](std::string_view d) {
    return std::all_of(d.begin(), d.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!all_digits(int_part) || !all_digits(frac_part) || (int_part.empty() && frac_part.empty())) {
    // Not a plain decimal: an exponent form goes through double (finite values only).
    if (s.find_first_of("eE") == std::string_view::npos) return std::nullopt;
    const auto v = ParseDouble(s);
    if (!v || !std::isfinite(*v) || std::abs(*v) > 9.0e18) return std::nullopt;
    return TimeValueFromDouble(*v);
  }
  std::int64_t whole = 0;
  if (!int_part.empty()) {
    const auto r = std::from_chars(int_part.data(), int_part.data() + int_part.size(), whole);
    if (r.ec != std::errc() || r.ptr != int_part.data() + int_part.size())
      return std::nullopt;  // overflow
  }
  double frac = 0.0;
  if (!frac_part.empty()) {
    const std::string f = "0." + std::string(frac_part);
    const auto r = std::from_chars(f.data(), f.data() + f.size(), frac);
    if (r.ec != std::errc()) return std::nullopt;
  }
  if (neg) return Normalised(-whole, -frac);
  return Normalised(whole, frac);
}

double TimeOrigin::relative_seconds(const TimeValue& t) const {
  std::int64_t dw = 0;
  double whole_diff;
  if (__builtin_sub_overflow(t.whole, value.whole, &dw))
    whole_diff = static_cast<double>(t.whole) - static_cast<double>(value.whole);
  else
    whole_diff = static_cast<double>(dw);
  const double units = whole_diff + (t.frac - value.frac);
  // Division by 1e9 (not multiplication by 1e-9) keeps whole nanoseconds correctly rounded.
  return units * static_cast<double>(NanosPerUnit(unit)) / 1e9;
}

std::optional<std::int64_t> TimeOrigin::nanoseconds() const {
  const std::int64_t npu = NanosPerUnit(unit);
  std::int64_t ns = 0;
  if (__builtin_mul_overflow(value.whole, npu, &ns)) return std::nullopt;
  const auto f = static_cast<std::int64_t>(std::llround(value.frac * static_cast<double>(npu)));
  if (__builtin_add_overflow(ns, f, &ns)) return std::nullopt;
  return ns;
}

std::optional<std::int64_t> TimeOrigin::absolute_ns(double relative_seconds) const {
  const auto o = nanoseconds();
  if (!o || !std::isfinite(relative_seconds) || std::abs(relative_seconds) > 9.0e9)
    return std::nullopt;
  std::int64_t out = 0;
  if (__builtin_add_overflow(*o, static_cast<std::int64_t>(std::llround(relative_seconds * 1e9)),
                             &out))
    return std::nullopt;
  return out;
}

}  // namespace imuconv::pipeline
