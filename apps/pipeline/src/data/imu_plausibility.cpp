#include "imuconv/pipeline/imu_plausibility.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "../io/message_text.h"
#include "imuconv/printable.h"

namespace imuconv::pipeline {

namespace {

// Standard gravity (m/s^2) and the bands around it. "Near g": [7, 13] m/s^2 holds the median
// |specific force| of any ground, handheld, aerial or automotive data set (gravity dominates;
// a sustained 3 m/s^2 horizontal acceleration moves |f| to 10.3 only); "near 1": [0.7, 1.3],
// the same band divided by g, so a data set in g whose median sits where one in m/s^2 would
// is recognised alike.
constexpr double kGravity = 9.80665;
constexpr double kNearGravityLow = 7.0, kNearGravityHigh = 13.0;
constexpr double kNearOneLow = kNearGravityLow / kGravity,
                 kNearOneHigh = kNearGravityHigh / kGravity;
// A median rate above 10 rad/s (573 deg/s) is sustained spinning no handheld, vehicle or
// aerial platform shows; the same numbers read as deg/s are 0.17 rad/s, ordinary motion.
constexpr double kImplausibleMedianGyro = 10.0;
// +-2000 deg/s, the largest full scale of common MEMS gyros (e.g. BMI088, ICM-42688, ADIS16470).
constexpr double kGyroFullScale = 2000.0 * M_PI / 180.0;
constexpr double kDegPerRad = 180.0 / M_PI;

double Median(std::vector<double>& v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  double m = *mid;
  if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), mid));
  return m;
}

}  // namespace

ImuMagnitudes MeasureMagnitudes(const std::vector<ImuSample>& samples) {
  ImuMagnitudes m;
  m.count = samples.size();
  if (samples.empty()) return m;
  std::vector<double> v(samples.size());
  std::size_t beyond = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    v[i] = samples[i].gyro.norm();
    beyond += v[i] > kGyroFullScale ? 1 : 0;
  }
  m.median_gyro = Median(v);
  m.beyond_gyro_range = static_cast<double>(beyond) / static_cast<double>(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) v[i] = samples[i].accel.norm();
  m.median_accel = Median(v);
  return m;
}

std::vector<std::string> ImuPlausibilityWarnings(const std::vector<ImuSample>& samples,
                                                 const std::string& source) {
  if (samples.size() < kPlausibilityMinSamples) return {};
  const ImuMagnitudes m = MeasureMagnitudes(samples);
  // A non-finite sample is the readers' error to report, not a unit question.
  if (!std::isfinite(m.median_gyro) || !std::isfinite(m.median_accel)) return {};
  const auto near = [](double x, double lo, double hi) { return x >= lo && x <= hi; };
  const std::string over = " over " + std::to_string(m.count) + " samples";
  const std::string where = Printable(source) + ": ";
  std::vector<std::string> out;
  const bool accel_near_g = near(m.median_accel, kNearGravityLow, kNearGravityHigh);
  const bool swapped = near(m.median_gyro, kNearGravityLow, kNearGravityHigh) && !accel_near_g;
  if (swapped) {
    out.push_back(
        where + "the gyro and accelerometer columns look swapped: median |gyro| " +
        Num(m.median_gyro, 4) +
        " (gravity's magnitude; angular rates in rad/s stay well below it) and median |accel| " +
        Num(m.median_accel, 4) + " (expected near 9.81 m/s^2, gravity)" + over +
        "; check the column order (wx, wy, wz, ax, ay, az)");
    return out;  // the unit checks below would read the swapped columns
  }
  if (near(m.median_accel, kNearOneLow, kNearOneHigh))
    out.push_back(where + "the accelerometer looks like it is in g, not m/s^2: median |accel| " +
                  Num(m.median_accel, 4) + over +
                  " (gravity alone is 9.81 m/s^2, 1 g); multiply it by 9.80665");
  if (m.median_gyro > kImplausibleMedianGyro) {
    std::string s = where + "the gyro looks like it is in deg/s, not rad/s: median |gyro| " +
                    Num(m.median_gyro, 4) + over + " (" + Num(m.median_gyro * kDegPerRad, 4) +
                    " deg/s if it were rad/s; " + Num(m.median_gyro / kDegPerRad, 4) +
                    " rad/s if it is deg/s)";
    if (m.beyond_gyro_range > 0)
      s += ", and " + Num(100.0 * m.beyond_gyro_range, 4) +
           "% of the samples exceed 34.9 rad/s, the +-2000 deg/s full scale of common MEMS gyros";
    out.push_back(s + "; multiply it by pi/180 = 0.0174533");
  }
  return out;
}

}  // namespace imuconv::pipeline
