#include "imuconv/window.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace imuconv {

Status MakeWindow(const ImuSample* samples, std::size_t n, double t_s, double t_e,
                  SampleWindow& out) {
  std::ostringstream msg;
  msg.precision(17);
  if (!(std::isfinite(t_s) && std::isfinite(t_e)) || !(t_e > t_s)) {
    msg << "interval [" << t_s << ", " << t_e << "] is empty or not finite";
    return Status::Error(msg.str());
  }
  if (n < 2 || samples == nullptr) return Status::Error("at least two IMU samples are needed");
  // A knot within a nanosecond of a sample is that sample (kSameInstant, window.h).
  const auto by_time = [](const ImuSample& s, double t) { return s.t < t; };
  const auto snap = [&](double t) {
    const std::size_t i =
        std::lower_bound(samples, samples + n, t - kSameInstant, by_time) - samples;
    return i < n && std::abs(samples[i].t - t) < kSameInstant ? samples[i].t : t;
  };
  t_s = snap(t_s);
  t_e = snap(t_e);
  if (!(t_e > t_s)) {
    msg << "interval [" << t_s << ", " << t_e
        << "] is shorter than a nanosecond (its ends are one sample)";
    return Status::Error(msg.str());
  }
  if (t_s < samples[0].t || t_e > samples[n - 1].t) {
    msg << "interval [" << t_s << ", " << t_e << "] is not covered by the IMU samples ["
        << samples[0].t << ", " << samples[n - 1].t << "]";
    return Status::Error(msg.str());
  }
  // i0: first sample with t >= t_s; i1: first sample with t >= t_e.
  const std::size_t i0 = std::lower_bound(samples, samples + n, t_s, by_time) - samples;
  const std::size_t i1 = std::lower_bound(samples, samples + n, t_e, by_time) - samples;
  out.samples = samples;
  if (samples[i0].t == t_s) {
    out.first = samples[i0];
    out.begin = i0 + 1;
  } else {
    out.first = InterpolateSample(samples[i0 - 1], samples[i0], t_s);
    out.begin = i0;
  }
  if (samples[i1].t == t_e) {
    out.last = samples[i1];
  } else {
    out.last = InterpolateSample(samples[i1 - 1], samples[i1], t_e);
  }
  out.end = std::max(out.begin, i1);
  return Status::Ok();
}

}  // namespace imuconv
