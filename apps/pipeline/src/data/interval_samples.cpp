// Intervals holding no IMU sample (imuconv/pipeline/interval_samples.h).
#include "imuconv/pipeline/interval_samples.h"

#include "../io/message_text.h"
#include "imuconv/pipeline/timing.h"
#include "imuconv/window.h"

namespace imuconv::pipeline {

std::optional<EmptyInterval> FindEmptyInterval(const std::vector<ImuSample>& s, std::size_t count,
                                               const std::function<double(std::size_t)>& time,
                                               IntervalEnds ends) {
  if (count < 2 || s.size() < 2) return std::nullopt;
  const bool included = ends == IntervalEnds::kIncluded;
  // The sample index j only moves forward: the first sample that can count for the current
  // interval (at or after its start within kSameInstant; strictly after it when ends are
  // excluded).
  std::size_t j = 0;
  double b = time(0);
  for (std::size_t k = 0; k + 1 < count; ++k) {
    const double a = b;
    b = time(k + 1);
    if (!(b > a) || a < s.front().t - kSameInstant || b > s.back().t + kSameInstant) continue;
    if (included) {
      while (j < s.size() && s[j].t < a - kSameInstant) ++j;
      if (j < s.size() && s[j].t <= b + kSameInstant) continue;
    } else {
      while (j < s.size() && s[j].t <= a + kSameInstant) ++j;
      if (j < s.size() && s[j].t < b - kSameInstant) continue;
    }
    std::vector<double> t(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) t[i] = s[i].t;
    return EmptyInterval{k, a, b, MedianPeriod(t)};
  }
  return std::nullopt;
}

std::string EmptyIntervalSentence(const EmptyInterval& e, IntervalEnds ends,
                                  std::optional<double> step, std::size_t intervals) {
  return "interval " + std::to_string(e.index) + " [" + Num(e.t_start, 10) + ", " +
         Num(e.t_end, 10) + "] s holds no IMU sample" +
         (ends == IntervalEnds::kExcluded ? " strictly inside it" : "") + ": " +
         (step ? "the keyframe step is " + Num(*step, 6) : "it is " + Num(e.t_end - e.t_start, 6)) +
         " s, the IMU period " + Num(e.median_period, 6) +
         " s (median), so it lies between two samples and is interpolation only (a step in the "
         "wrong unit?); " +
         std::to_string(intervals) + " intervals in all";
}

}  // namespace imuconv::pipeline
