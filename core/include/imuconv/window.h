// SampleWindow: the knots spanning one interval [t_s, t_e].
//
// Knot 0 is at t_s and the last knot is at t_e; where t_s or t_e falls between two
// samples its value is interpolated linearly. Interior knots are the samples strictly
// inside (t_s, t_e), referenced in place (no copy). Integrators decide how to use the
// knots: zero-order hold uses knot j over [t_j, t_j+1]; RK4 interpolates linearly.
#pragma once

#include <cstddef>
#include <string>

#include "imuconv/export.h"
#include "imuconv/status.h"
#include "imuconv/types.h"

namespace imuconv {

struct SampleWindow {
  const ImuSample* samples = nullptr;  ///< interior samples, [begin, end)
  std::size_t begin = 0, end = 0;
  ImuSample first, last;

  std::size_t size() const noexcept { return end - begin + 2; }
  const ImuSample& operator[](std::size_t j) const noexcept {
    if (j == 0) return first;
    if (j + 1 == size()) return last;
    return samples[begin + j - 1];
  }
  double t_start() const noexcept { return first.t; }
  double t_end() const noexcept { return last.t; }
};

/// Linear interpolation of two samples at time t.
inline ImuSample InterpolateSample(const ImuSample& a, const ImuSample& b, double t) {
  ImuSample s;
  s.t = t;
  const double u = (t - a.t) / (b.t - a.t);
  s.gyro = a.gyro + u * (b.gyro - a.gyro);
  s.accel = a.accel + u * (b.accel - a.accel);
  return s;
}

/// Builds the window of [t_s, t_e] over samples sorted by strictly increasing time.
/// Fails if the interval is empty or not covered by the samples.
IMUCONV_API Status MakeWindow(const ImuSample* samples, std::size_t n, double t_s, double t_e, SampleWindow& out);

}  // namespace imuconv
