#include "row_loop.h"

#include <charconv>
#include <cmath>

#include "csv_text.h"

namespace imuconv::pipeline::data {

RowLoop::RowLoop(std::string path, LineReader& lines, RowFormat format,
                 std::optional<TimeOrigin> origin)
    : path_(std::move(path)),
      lines_(lines),
      f_(std::move(format)),
      have_origin_(origin.has_value()) {
  if (origin) origin_ = *origin;
  origin_.unit = origin ? origin->unit : f_.unit;
  delimited_ = " separated by " + DelimiterName(f_.delimiter, f_.whitespace_delimited);
}

void RowLoop::fail(const std::string& message) const { throw ReadError(path_, line_no_, message); }

double RowLoop::number(std::size_t index, const std::string& label) const {
  const std::string_view text = fields_[index];
  const auto v = ParseDouble(text);
  if (!v || !std::isfinite(*v))
    fail("column " + std::to_string(index) + " (" + label + "): expected a finite number, found " +
         Shown(text));
  return *v;
}

TimeValue RowLoop::parse_time() const {
  const std::string_view text = fields_[f_.time_index];
  std::optional<TimeValue> tv;
  if (f_.integer_time) {
    std::int64_t whole = 0;
    const std::string_view tt = Trim(text);
    const auto r = std::from_chars(tt.data(), tt.data() + tt.size(), whole);
    if (!tt.empty() && r.ec == std::errc() && r.ptr == tt.data() + tt.size())
      tv = TimeValue{whole, 0.0};
  } else {
    tv = ParseTimeValue(text);
  }
  if (!tv)
    fail("column " + std::to_string(f_.time_index) + " (" + f_.time_label + "): expected " +
         f_.time_what + ", found " + Shown(text));
  return *tv;
}

double RowLoop::relative(const TimeValue& tv) const {
  if (origin_.unit == f_.unit) return origin_.relative_seconds(tv);
  if (NanosPerUnit(f_.unit) > NanosPerUnit(origin_.unit)) {
    // A coarser file on a finer axis (TUM seconds on EuRoC's nanoseconds): the stamp in the
    // origin's unit, whole units exactly where they fit in int64.
    const std::int64_t ratio = NanosPerUnit(f_.unit) / NanosPerUnit(origin_.unit);
    std::int64_t whole = 0;
    if (__builtin_mul_overflow(tv.whole, ratio, &whole))
      fail("timestamp is out of range on the IMU's time axis");
    const double scaled = tv.frac * static_cast<double>(ratio), floor_scaled = std::floor(scaled);
    return origin_.relative_seconds(
        TimeValue{whole + static_cast<std::int64_t>(floor_scaled), scaled - floor_scaled});
  }
  // The stamp in the origin's (coarser) unit first, so that the difference stays exact:
  // whole units and the remainder as the fraction.
  const std::int64_t ratio = NanosPerUnit(origin_.unit) / NanosPerUnit(f_.unit);
  std::int64_t whole = tv.whole / ratio, rem = tv.whole % ratio;
  if (rem < 0) {
    whole -= 1;
    rem += ratio;
  }
  return origin_.relative_seconds(
      TimeValue{whole, (static_cast<double>(rem) + tv.frac) / static_cast<double>(ratio)});
}

bool RowLoop::next() {
  while (lines_.next(line_)) {
    if (IsBlank(line_)) continue;
    if (!f_.comment.empty() && Trim(line_).substr(0, f_.comment.size()) == f_.comment) continue;
    Split(line_, f_.delimiter, f_.whitespace_delimited, fields_);
    line_no_ = lines_.line_no();
    if (f_.n_fields == 0) {
      f_.n_fields = fields_.size();
      if (fields_.size() < f_.min_fields)
        fail("expected at least " + std::to_string(f_.min_fields) + " fields" + delimited_ +
             f_.min_fields_why + ", found " + std::to_string(fields_.size()));
    }
    if (fields_.size() != f_.n_fields)
      fail("expected " + std::to_string(f_.n_fields) + " fields" + f_.fields_what + delimited_ +
           ", found " + std::to_string(fields_.size()));
    // From here on every field index of the format is in range (n_fields >= min_fields).
    const TimeValue tv = parse_time();
    if (prev_line_ == 0) {
      if (!have_origin_) origin_.value = tv;
    } else if (!(tv.whole > prev_.whole || (tv.whole == prev_.whole && tv.frac > prev_.frac))) {
      fail("timestamp " + ShownBare(Trim(fields_[f_.time_index])) +
           " is not after the previous sample's (line " + std::to_string(prev_line_) +
           "); timestamps must be strictly increasing");
    }
    const double t = relative(tv);
    if (prev_line_ != 0 && !(t > t_))
      fail(std::string("timestamp is too close to the previous ") + f_.row_noun +
           "'s to be told apart in double seconds");
    prev_ = tv;
    prev_line_ = line_no_;
    t_ = t;
    return true;
  }
  return false;
}

}  // namespace imuconv::pipeline::data
