#include "imuconv/pipeline/imu_plausibility.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "../io/message_text.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/printable.h"
#include "imuconv/so3.h"

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

// Poses against the gyro (docs/imu-plausibility.md, "Poses against the gyro"). Windows of 0.5 s:
// long enough for ordinary motion to turn by a tenth of a radian, short enough that the gyro
// bias (0.08 rad/s on EuRoC V1_01) moves each window's rotation by a few hundredths only, and
// that offset is the same in every window, so it is fitted out. A window spanning more than
// 1 s holds a gap of the poses and is skipped.
constexpr double kPoseWindow = 0.5, kPoseWindowMax = 1.0;
// A window counts when the gyro turns by more than 0.05 rad in it; 20 such windows are the
// least the fit and its median are judged on.
constexpr double kMinWindowRotation = 0.05;
constexpr std::size_t kMinRotatingWindows = 20;
// The median residual above which the poses are suspect. EuRoC V1_01 (vicon2gt ground truth):
// 0.0012 rad over the whole file (216 windows), 0.0011 over the examples' slice; its quaternions
// with their components in the other order: 0.049 and 0.056; the poses 0.1 s late: 0.029.
constexpr double kMaxMedianResidual = 0.02;

// The gyro's rotation from t0 to t1: the product of Exp(w dt), each sample's rate held until
// the next sample (the samples cover [t0, t1]).
Mat3 GyroRotation(const std::vector<ImuSample>& samples, double t0, double t1) {
  auto k = static_cast<std::size_t>(
      std::upper_bound(samples.begin(), samples.end(), t0,
                       [](double t, const ImuSample& s) { return t < s.t; }) -
      samples.begin() - 1);
  Mat3 R = Mat3::Identity();
  for (; k + 1 < samples.size() && samples[k].t < t1; ++k) {
    const double dt = std::min(samples[k + 1].t, t1) - std::max(samples[k].t, t0);
    if (dt > 0) R = R * so3::Exp(samples[k].gyro * dt);
  }
  return R;
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

std::vector<std::string> PoseGyroWarnings(const std::vector<ImuSample>& samples,
                                          const GroundTruth& poses, const std::string& poses_name) {
  if (samples.size() < 2 || poses.t.size() < 2) return {};
  // Each rotating window's rotation vectors: the poses' (in their sensor frame) and the gyro's.
  std::vector<Vec3> pose_phi, gyro_phi;
  for (std::size_t i = 0, j = 0; i + 1 < poses.t.size(); i = j) {
    j = i + 1;
    while (j < poses.t.size() && poses.t[j] < poses.t[i] + kPoseWindow) ++j;
    if (j == poses.t.size()) break;
    const double t0 = poses.t[i], t1 = poses.t[j];
    if (t1 - t0 > kPoseWindowMax || t0 < samples.front().t || t1 > samples.back().t) continue;
    const Vec3 g = so3::Log(GyroRotation(samples, t0, t1));
    const Vec3 p = so3::Log(poses.x[i].R.transpose() * poses.x[j].R);
    if (!g.allFinite() || !p.allFinite() || g.norm() <= kMinWindowRotation) continue;
    gyro_phi.push_back(g);
    pose_phi.push_back(p);
  }
  const std::size_t n = gyro_phi.size();
  if (n < kMinRotatingWindows) return {};  // too little rotation: no judgment
  // The angles alone cannot tell: the relative rotation's angle is 2 acos|q_i . q_j|, which no
  // reordering of the quaternions' components changes. The axes can: a constant rotation C
  // between the gyro's frame and the poses' (an extrinsic, vicon0 without T_BS) and a constant
  // offset c (the bias times the window) are fitted, p = C (g - c), by the orthogonal
  // Procrustes solution on the centred vectors; a pose file in the wrong component order turns
  // about the world's axes, which no constant C maps the gyro's onto.
  Vec3 mean_g = Vec3::Zero(), mean_p = Vec3::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    mean_g += gyro_phi[k] / static_cast<double>(n);
    mean_p += pose_phi[k] / static_cast<double>(n);
  }
  Mat3 H = Mat3::Zero();
  for (std::size_t k = 0; k < n; ++k)
    H += (gyro_phi[k] - mean_g) * (pose_phi[k] - mean_p).transpose();
  const Eigen::JacobiSVD<Mat3> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Mat3 C = svd.matrixV() * D * svd.matrixU().transpose();
  std::vector<double> residual(n), angle(n);
  for (std::size_t k = 0; k < n; ++k) {
    residual[k] = ((pose_phi[k] - mean_p) - C * (gyro_phi[k] - mean_g)).norm();
    angle[k] = gyro_phi[k].norm();
  }
  const double median_residual = Median(residual);
  if (!(median_residual > kMaxMedianResidual)) return {};
  return {Printable(poses_name) + ": the poses' rotations disagree with the gyro: over " +
          std::to_string(n) + " windows of 0.5 s turning a median " + Num(Median(angle), 4) +
          " rad, the rotation between poses differs from the gyro's integrated rotation by a "
          "median " +
          Num(median_residual, 4) +
          " rad after fitting a constant rotation between their frames and a constant gyro bias "
          "(EuRoC V1_01's own ground truth: 0.0012 rad); check the quaternion order (w,x,y,z or "
          "x,y,z,w), that the poses are of this sequence and on its time axis, and that angles "
          "are in radians"};
}

}  // namespace imuconv::pipeline
