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

/// Two times closer than this are one instant: a knot (t_s or t_e) within it of a sample is
/// that sample, its time and values, not an interpolation beside it. Every timestamp format
/// read (EuRoC, Basalt, the pipeline's *_abs_ns) has a resolution of 1 ns; a keyframe computed
/// as k x 0.1 s lies 4e-17 s off the sample at 0.3 s, and kept apart, the two would make a
/// step of 4e-17 s (Basalt, which counts integer nanoseconds, refuses it; the others integrate
/// a step that means nothing). IMU samples are at least 1e-5 s apart (100 kHz), so at most one
/// sample is that close to a knot.
inline constexpr double kSameInstant = 1e-9;

/// Builds the window of [t_s, t_e] over samples sorted by strictly increasing time.
/// Fails if the interval is empty or not covered by the samples. t_s and t_e are first
/// moved onto a sample within kSameInstant of them.
IMUCONV_API Status MakeWindow(const ImuSample* samples, std::size_t n, double t_s, double t_e,
                              SampleWindow& out);

}  // namespace imuconv
