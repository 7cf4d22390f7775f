// ORB-SLAM3's preintegration, tracking prediction and EdgeInertial, in its own precision
// (imuconv/kernels/orb_slam3.h has the scheme, the noise and the error states).
#include "imuconv/kernels/orb_slam3.h"

#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace imuconv::kernels {
namespace {

template <typename Scalar>
Eigen::Matrix<Scalar, 3, 3> Hat(const Eigen::Matrix<Scalar, 3, 1>& v) {
  Eigen::Matrix<Scalar, 3, 3> m;
  m << Scalar(0), -v.z(), v.y(), v.z(), Scalar(0), -v.x(), -v.y(), v.x(), Scalar(0);
  return m;
}

/// The nearest rotation by SVD, U V^T (IMU::NormalizeRotation).
template <typename Scalar>
Eigen::Matrix<Scalar, 3, 3> NormalizeRotation(const Eigen::Matrix<Scalar, 3, 3>& R) {
  const Eigen::JacobiSVD<Eigen::Matrix<Scalar, 3, 3>> svd(
      R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

/// IntegratedRotation: Exp(w dt) and its right Jacobian, first order (I + W and I) below
/// |w dt| = 1e-4. Upstream calls the unqualified sin and cos of <math.h> on its float angle:
/// they compute in double, and `1 - cos(d)` and `d - sin(d)` are then formed in double
/// before Eigen rounds each coefficient to float. (In float, 1 - cosf(d) would lose about
/// 1e-3 of its value to cancellation at d = 0.01, and the rotation would drift by about 1e-4
/// over 2000 steps from ORB-SLAM3's own.)
void StepRotation(const Vec3f& w_dt, Mat3f& delta_R, Mat3f& right_J) {
  // x^2 + y^2 + z^2 from the left, as upstream writes it (Eigen's squaredNorm() adds
  // x^2 + (y^2 + z^2), which differs in the last bit now and then).
  const float d2 = w_dt.x() * w_dt.x() + w_dt.y() * w_dt.y() + w_dt.z() * w_dt.z();
  const float d = static_cast<float>(std::sqrt(static_cast<double>(d2)));
  const Mat3f W = Hat(w_dt);
  if (d < 1e-4f) {
    delta_R = Mat3f::Identity() + W;
    right_J = Mat3f::Identity();
  } else {
    const double dd = d;
    const float sin_d = static_cast<float>(std::sin(dd));
    const float one_minus_cos = static_cast<float>(1.0 - std::cos(dd));
    const float d_minus_sin = static_cast<float>(dd - std::sin(dd));
    delta_R = Mat3f::Identity() + W * sin_d / d + W * W * one_minus_cos / d2;
    right_J = Mat3f::Identity() - W * one_minus_cos / d2 + W * W * d_minus_sin / (d2 * d);
  }
}

/// Exp in float through the unit quaternion, as the Sophus SO3f::exp that GetDeltaRotation
/// calls evaluates it: float sin and cos of the half angle, a Taylor series below an angle
/// of 1e-5, the quaternion used as it comes (not normalized again).
Mat3f ExpFloat(const Vec3f& phi) {
  const float theta_sq = phi.squaredNorm();
  const float theta = std::sqrt(theta_sq);
  const float half = 0.5f * theta;
  float imag, real;
  if (theta_sq < 1e-5f * 1e-5f) {
    const float theta_po4 = theta_sq * theta_sq;
    imag = 0.5f - theta_sq / 48.0f + theta_po4 / 3840.0f;
    real = 1.0f - theta_sq / 8.0f + theta_po4 / 384.0f;
  } else {
    imag = std::sin(half) / theta;
    real = std::cos(half);
  }
  const Eigen::Quaternionf q(real, imag * phi.x(), imag * phi.y(), imag * phi.z());
  return q.toRotationMatrix();
}

// EdgeInertial's SO(3) functions, in double, with upstream's 1e-5 thresholds.
Vec3 LogDouble(const Mat3& R) {
  const double tr = R(0, 0) + R(1, 1) + R(2, 2);
  const Vec3 w((R(2, 1) - R(1, 2)) / 2, (R(0, 2) - R(2, 0)) / 2, (R(1, 0) - R(0, 1)) / 2);
  const double cos_theta = (tr - 1.0) * 0.5;
  if (cos_theta > 1 || cos_theta < -1) return w;
  const double theta = std::acos(cos_theta);
  const double s = std::sin(theta);
  if (std::abs(s) < 1e-5) return w;
  return theta * w / s;
}
Mat3 InverseRightJacobianDouble(const Vec3& v) {
  const double d2 = v.squaredNorm();
  const double d = std::sqrt(d2);
  if (d < 1e-5) return Mat3::Identity();
  const Mat3 W = Hat(v);
  return Mat3::Identity() + W / 2 +
         W * W * (1.0 / d2 - (1.0 + std::cos(d)) / (2.0 * d * std::sin(d)));
}
Mat3 RightJacobianDouble(const Vec3& v) {
  const double d2 = v.squaredNorm();
  const double d = std::sqrt(d2);
  if (d < 1e-5) return Mat3::Identity();
  const Mat3 W = Hat(v);
  return Mat3::Identity() - W * (1.0 - std::cos(d)) / d2 + W * W * (d - std::sin(d)) / (d2 * d);
}

constexpr float kGravity = 9.81f;  // IMU::GRAVITY_VALUE

}  // namespace

OrbSlam3Calib OrbSlam3CalibFromDensities(const ImuNoise& densities, double frequency_hz) {
  const float sf = std::sqrt(static_cast<float>(frequency_hz));
  const float ng = static_cast<float>(densities.gyro_noise_density) * sf;
  const float na = static_cast<float>(densities.accel_noise_density) * sf;
  const float ngw = static_cast<float>(densities.gyro_random_walk) / sf;
  const float naw = static_cast<float>(densities.accel_random_walk) / sf;
  OrbSlam3Calib c;
  c.cov << ng * ng, ng * ng, ng * ng, na * na, na * na, na * na;
  c.cov_walk << ngw * ngw, ngw * ngw, ngw * ngw, naw * naw, naw * naw, naw * naw;
  return c;
}

Status OrbSlam3Steps(const std::vector<ImuSample>& samples, std::vector<OrbSlam3Step>& steps) {
  if (samples.size() < 2)
    return Status::Error("ORB-SLAM3 preintegration: needs at least two samples");
  steps.clear();
  steps.reserve(samples.size() - 1);
  for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
    if (!(samples[k + 1].t > samples[k].t))
      return Status::Error("ORB-SLAM3 preintegration: sample " + std::to_string(k + 1) +
                           "'s time is not after the previous one's");
    // IMU::Point stores the readings in float; Tracking averages them in float.
    const Vec3f a0 = samples[k].accel.cast<float>(), a1 = samples[k + 1].accel.cast<float>();
    const Vec3f w0 = samples[k].gyro.cast<float>(), w1 = samples[k + 1].gyro.cast<float>();
    OrbSlam3Step s;
    s.accel = (a0 + a1) * 0.5f;
    s.gyro = (w0 + w1) * 0.5f;
    s.dt = static_cast<float>(samples[k + 1].t - samples[k].t);
    if (!s.accel.allFinite() || !s.gyro.allFinite())
      return Status::Error("ORB-SLAM3 preintegration: sample " + std::to_string(k) +
                           " is not finite in float");
    steps.push_back(s);
  }
  return Status::Ok();
}

OrbSlam3Preintegrated PreintegrateOrbSlam3(const std::vector<OrbSlam3Step>& steps,
                                           const OrbSlam3Calib& calib, const OrbSlam3Bias& b) {
  OrbSlam3Preintegrated p;
  p.b = b;
  p.steps = steps;
  const Eigen::Matrix<float, 6, 6> Nga = calib.cov.asDiagonal();
  const Eigen::Matrix<float, 6, 6> NgaWalk = calib.cov_walk.asDiagonal();
  for (const OrbSlam3Step& s : steps) {
    const float dt = s.dt;
    const Vec3f acc = s.accel - b.ba;
    const Vec3f w = s.gyro - b.bg;
    p.avgA = (p.dT * p.avgA + p.dR * acc * dt) / (p.dT + dt);
    p.avgW = (p.dT * p.avgW + w * dt) / (p.dT + dt);

    // Position, then velocity, with the rotation before this step.
    p.dP = p.dP + p.dV * dt + 0.5f * p.dR * acc * dt * dt;
    p.dV = p.dV + p.dR * acc * dt;
    const Mat3f W_acc = Hat(acc);
    Eigen::Matrix<float, 9, 9> A = Eigen::Matrix<float, 9, 9>::Identity();
    Eigen::Matrix<float, 9, 6> B = Eigen::Matrix<float, 9, 6>::Zero();
    A.block<3, 3>(3, 0) = -p.dR * dt * W_acc;
    A.block<3, 3>(6, 0) = -0.5f * p.dR * dt * dt * W_acc;
    A.block<3, 3>(6, 3) = Mat3f::Identity() * dt;
    B.block<3, 3>(3, 3) = p.dR * dt;
    B.block<3, 3>(6, 3) = 0.5f * p.dR * dt * dt;

    p.JPa = p.JPa + p.JVa * dt - 0.5f * p.dR * dt * dt;
    p.JPg = p.JPg + p.JVg * dt - 0.5f * p.dR * dt * dt * W_acc * p.JRg;
    p.JVa = p.JVa - p.dR * dt;
    p.JVg = p.JVg - p.dR * dt * W_acc * p.JRg;

    Mat3f delta_R, right_J;
    StepRotation(w * dt, delta_R, right_J);
    p.dR = NormalizeRotation<float>(p.dR * delta_R);
    A.block<3, 3>(0, 0) = delta_R.transpose();
    B.block<3, 3>(0, 0) = right_J * dt;
    p.C.block<9, 9>(0, 0) = A * p.C.block<9, 9>(0, 0) * A.transpose() + B * Nga * B.transpose();
    p.C.block<6, 6>(9, 9) += NgaWalk;
    p.JRg = delta_R.transpose() * p.JRg - right_J * dt;
    p.dT += dt;
  }
  return p;
}

Mat3f OrbSlam3DeltaRotation(const OrbSlam3Preintegrated& pre, const OrbSlam3Bias& b) {
  const Vec3f dbg = b.bg - pre.b.bg;
  return NormalizeRotation<float>(pre.dR * ExpFloat(pre.JRg * dbg));
}
Vec3f OrbSlam3DeltaVelocity(const OrbSlam3Preintegrated& pre, const OrbSlam3Bias& b) {
  return pre.dV + pre.JVg * (b.bg - pre.b.bg) + pre.JVa * (b.ba - pre.b.ba);
}
Vec3f OrbSlam3DeltaPosition(const OrbSlam3Preintegrated& pre, const OrbSlam3Bias& b) {
  return pre.dP + pre.JPg * (b.bg - pre.b.bg) + pre.JPa * (b.ba - pre.b.ba);
}

OrbSlam3Pose<float> PredictOrbSlam3Tracking(const OrbSlam3Preintegrated& pre,
                                            const OrbSlam3Pose<float>& start) {
  const Vec3f g(0.0f, 0.0f, -kGravity);
  const float t12 = pre.dT;
  OrbSlam3Pose<float> end;
  end.R = NormalizeRotation<float>(start.R * OrbSlam3DeltaRotation(pre, pre.b));
  end.p =
      start.p + start.v * t12 + 0.5f * t12 * t12 * g + start.R * OrbSlam3DeltaPosition(pre, pre.b);
  end.v = start.v + t12 * g + start.R * OrbSlam3DeltaVelocity(pre, pre.b);
  return end;
}

OrbSlam3Pose<double> PredictOrbSlam3(const OrbSlam3Preintegrated& pre,
                                     const OrbSlam3Pose<double>& start) {
  const Vec3 g(0.0, 0.0, -static_cast<double>(kGravity));
  const double dT = pre.dT;
  OrbSlam3Pose<double> end;
  end.R = NormalizeRotation<double>(start.R * pre.dR.cast<double>());
  end.p = start.p + start.v * dT + 0.5 * g * dT * dT + start.R * pre.dP.cast<double>();
  end.v = start.v + g * dT + start.R * pre.dV.cast<double>();
  return end;
}

Mat9 OrbSlam3EdgeInformation(const OrbSlam3Preintegrated& pre) {
  Mat9 info = pre.C.block<9, 9>(0, 0).cast<double>().inverse();
  info = (info + info.transpose()) / 2;
  const Eigen::SelfAdjointEigenSolver<Mat9> es(info);
  Vec9 eigs = es.eigenvalues();
  for (int i = 0; i < 9; ++i)
    if (eigs[i] < 1e-12) eigs[i] = 0;
  return es.eigenvectors() * eigs.asDiagonal() * es.eigenvectors().transpose();
}

OrbSlam3EdgeInertial EvaluateOrbSlam3EdgeInertial(const OrbSlam3Preintegrated& pre,
                                                  const OrbSlam3Pose<double>& s1, const Vec3& bg1,
                                                  const Vec3& ba1, const OrbSlam3Pose<double>& s2) {
  const OrbSlam3Bias b1{bg1.cast<float>(), ba1.cast<float>()};
  const Vec3 g(0.0, 0.0, -static_cast<double>(kGravity));
  const double dt = pre.dT;
  const Mat3 dR = OrbSlam3DeltaRotation(pre, b1).cast<double>();
  const Vec3 dV = OrbSlam3DeltaVelocity(pre, b1).cast<double>();
  const Vec3 dP = OrbSlam3DeltaPosition(pre, b1).cast<double>();
  const Mat3 Rbw1 = s1.R.transpose();

  OrbSlam3EdgeInertial e;
  e.information = OrbSlam3EdgeInformation(pre);
  const Mat3 eR = dR.transpose() * Rbw1 * s2.R;
  const Vec3 er = LogDouble(eR);
  const Vec3 dv_world = s2.v - s1.v - g * dt;
  const Vec3 dp_world = s2.p - s1.p - s1.v * dt - g * dt * dt / 2;
  e.residual << er, Rbw1 * dv_world - dV, Rbw1 * dp_world - dP;
  e.chi2 = e.residual.dot(e.information * e.residual);

  // The bias change as IMU::Bias holds it (float), then in double.
  const Vec3 dbg = (b1.bg - pre.b.bg).cast<double>();
  const Mat3 invJr = InverseRightJacobianDouble(er);
  const Mat3 JRg = pre.JRg.cast<double>();
  e.J_pose1.block<3, 3>(0, 0) = -invJr * s2.R.transpose() * s1.R;
  e.J_pose1.block<3, 3>(3, 0) = Hat<double>(Rbw1 * dv_world);
  e.J_pose1.block<3, 3>(6, 0) = Hat<double>(Rbw1 * (s2.p - s1.p - s1.v * dt - 0.5 * g * dt * dt));
  e.J_pose1.block<3, 3>(6, 3) = -Mat3::Identity();
  e.J_vel1.block<3, 3>(3, 0) = -Rbw1;
  e.J_vel1.block<3, 3>(6, 0) = -Rbw1 * dt;
  e.J_gyro_bias1.block<3, 3>(0, 0) = -invJr * eR.transpose() * RightJacobianDouble(JRg * dbg) * JRg;
  e.J_gyro_bias1.block<3, 3>(3, 0) = -pre.JVg.cast<double>();
  e.J_gyro_bias1.block<3, 3>(6, 0) = -pre.JPg.cast<double>();
  e.J_acc_bias1.block<3, 3>(3, 0) = -pre.JVa.cast<double>();
  e.J_acc_bias1.block<3, 3>(6, 0) = -pre.JPa.cast<double>();
  e.J_pose2.block<3, 3>(0, 0) = invJr;
  e.J_pose2.block<3, 3>(6, 3) = Rbw1 * s2.R;
  e.J_vel2.block<3, 3>(3, 0) = Rbw1;
  return e;
}

}  // namespace imuconv::kernels
