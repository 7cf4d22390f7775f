#include "imuconv/pipeline/timing.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <iterator>
#include <stdexcept>
#include <string>

#include "../io/message_text.h"

namespace imuconv::pipeline {

namespace {

// The four time units, one row each: what NanosPerUnit, TimeUnitName, ParseTimeUnit and the
// rate message's long name read, so that a unit's numbers and names are written once.
struct TimeUnitRow {
  TimeUnit unit;
  std::int64_t nanos;     // nanoseconds per unit
  const char* name;       // as in a pipeline's "time_unit"
  const char* long_name;  // in messages
};
constexpr TimeUnitRow kTimeUnits[] = {
    {TimeUnit::s, 1000000000, "s", "seconds"},
    {TimeUnit::ms, 1000000, "ms", "milliseconds"},
    {TimeUnit::us, 1000, "us", "microseconds"},
    {TimeUnit::ns, 1, "ns", "nanoseconds"},
};

constexpr bool RowsInEnumOrder() {
  for (std::size_t i = 0; i < std::size(kTimeUnits); ++i)
    if (static_cast<std::size_t>(kTimeUnits[i].unit) != i) return false;
  return true;
}
static_assert(RowsInEnumOrder(), "kTimeUnits lists the units in TimeUnit's order");

// A unit's row, by index as the switches it replaces were (NanosPerUnit runs per sample, in
// RowLoop::relative). The enum is closed: a value cast from outside it is a broken invariant,
// reported as such instead of read past the table.
const TimeUnitRow& RowOf(TimeUnit u) {
  const auto i = static_cast<std::size_t>(u);
  if (i >= std::size(kTimeUnits))
    throw std::logic_error("TimeUnit " + std::to_string(static_cast<int>(u)) + " has no row");
  return kTimeUnits[i];
}

}  // namespace

std::int64_t NanosPerUnit(TimeUnit u) { return RowOf(u).nanos; }

const char* TimeUnitName(TimeUnit u) { return RowOf(u).name; }

std::optional<TimeUnit> ParseTimeUnit(const std::string& s) {
  for (const TimeUnitRow& row : kTimeUnits)
    if (s == row.name) return row.unit;
  return std::nullopt;
}

namespace {

std::string GapAdvice(TimeSource source) {
  switch (source) {
    case TimeSource::ground_truth:
      return "set \"allow_gaps\": true in the ground_truth object to interpolate across it";
    case TimeSource::imu_array:
      return "pass allow_gaps=True to integrate across it";
    default:
      return "set \"allow_gaps\": true in the IMU source to integrate across it";
  }
}

bool PlausibleRate(double hz) { return hz >= kMinRateHz && hz <= kMaxRateHz; }

// The unit the stamps were most likely written in: among the units that turn the median
// period into a plausible rate, the one whose rate is nearest (on a log scale) to 300 Hz,
// the middle of the usual IMU range of 100 Hz to 1 kHz. Units are 1000x apart and the
// plausible range spans 5 decades, so at most two units qualify; the log distance picks
// 100 Hz over 100 kHz, say.
std::optional<TimeUnit> LikelyUnit(double period_s, TimeUnit declared) {
  // The period as a number in the file's own unit.
  const double in_units = period_s * 1e9 / static_cast<double>(NanosPerUnit(declared));
  std::optional<TimeUnit> best;
  double best_distance = 0.0;
  for (const TimeUnitRow& row : kTimeUnits) {
    const TimeUnit u = row.unit;
    if (u == declared) continue;
    const double rate = 1e9 / (in_units * static_cast<double>(NanosPerUnit(u)));
    if (!PlausibleRate(rate)) continue;
    const double distance = std::abs(std::log10(rate) - std::log10(300.0));
    if (!best || distance < best_distance) {
      best = u;
      best_distance = distance;
    }
  }
  return best;
}

std::string RateMessage(double period, TimeUnit declared, TimeSource source) {
  std::string m =
      "the median period is " + Num(period) + " s (rate " + Num(1.0 / period) + " Hz); ";
  const auto likely = LikelyUnit(period, declared);
  const std::string range =
      " (" + std::string(source == TimeSource::ground_truth ? "a ground-truth" : "an IMU") +
      " rate is expected between 1 Hz and 100 kHz)";
  if (!likely) {
    m += "no time unit (s, ms, us, ns) gives a plausible rate: check the time column";
    if (source == TimeSource::imu) m += " and time_unit";
    if (source == TimeSource::imu_array) m += " (the samples' t must be in seconds)";
    return m + range;
  }
  m += std::string("the timestamps look like ") + RowOf(*likely).long_name;
  switch (source) {
    case TimeSource::imu:
      m += std::string(": set time_unit to \"") + TimeUnitName(*likely) + "\"";
      break;
    case TimeSource::imu_euroc:
      m += std::string(
               ", but the EuRoC format reads nanoseconds: convert them, or read the file with "
               "\"format\": \"csv\" "
               "and \"time_unit\": \"") +
           TimeUnitName(*likely) + "\"";
      break;
    case TimeSource::ground_truth:
      m += ", but ground-truth files are read in nanoseconds: convert them";
      break;
    case TimeSource::imu_array:
      m += ", but the samples' t must be in seconds: convert them";
      break;
  }
  return m + range;
}

}  // namespace

double MedianPeriod(const std::vector<double>& t) {
  if (t.size() < 2) return 0.0;
  std::vector<double> d(t.size() - 1);
  for (std::size_t i = 1; i < t.size(); ++i) d[i - 1] = t[i] - t[i - 1];
  const auto mid = d.begin() + static_cast<std::ptrdiff_t>((d.size() - 1) / 2);
  std::nth_element(d.begin(), mid, d.end());
  return *mid;
}

std::optional<TimingIssue> FindTimingIssue(const std::vector<double>& t, const TimingPolicy& policy,
                                           TimeUnit declared, TimeSource source) {
  return FindTimingIssue(t, MedianPeriod(t), policy, declared, source);
}

std::optional<TimingIssue> FindTimingIssue(const std::vector<double>& t, double median,
                                           const TimingPolicy& policy, TimeUnit declared,
                                           TimeSource source) {
  if (t.size() < 2 || !(median > 0.0) || !std::isfinite(median)) return std::nullopt;
  // The rate first: a wrong unit makes every gap message beside the point.
  if (!PlausibleRate(1.0 / median))
    return TimingIssue{TimingIssue::Kind::rate, 0, RateMessage(median, declared, source), median};
  if (policy.allow_gaps) return std::nullopt;
  const double factor = std::isfinite(policy.max_gap_factor) && policy.max_gap_factor >= 1.0
                            ? policy.max_gap_factor
                            : TimingPolicy{}.max_gap_factor;
  const double limit = factor * median;
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double gap = t[i] - t[i - 1];
    if (!(gap > limit)) continue;
    const bool gt = source == TimeSource::ground_truth;
    return TimingIssue{TimingIssue::Kind::gap,
                       i,
                       "gap of " + Num(gap) + " s before this " + (gt ? "row" : "sample") +
                           " (the median period is " + Num(median) + " s; limit " + Num(factor) +
                           " x median = " + Num(limit) + " s); " + GapAdvice(source),
                       median,
                       gap,
                       limit};
  }
  return std::nullopt;
}

}  // namespace imuconv::pipeline
