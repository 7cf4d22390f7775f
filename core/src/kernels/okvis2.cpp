// OKVIS2's ImuError propagation, preintegration and residual (imuconv/kernels/okvis2.h has
// the scheme, the error states and the noise interpretation).
#include "imuconv/kernels/okvis2.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "imuconv/so3.h"

#include <Eigen/Eigenvalues>

namespace imuconv::kernels {
namespace {

using Mat4 = Eigen::Matrix4d;

constexpr std::int64_t kNanosecondsPerSecond = 1000000000;

/// sin(x)/x, by its Taylor series to x^6 below |x| = 1e-6 as OKVIS evaluates it.
double Sinc(double x) {
  if (std::abs(x) > 1e-6) return std::sin(x) / x;
  const double x2 = x * x;
  return 1.0 - x2 / 6.0 + x2 * x2 / 120.0 - x2 * x2 * x2 / 5040.0;
}

/// The unit quaternion of the rotation vector phi (OKVIS's deltaQ; exp(w dt) is deltaQ(w dt)).
Eigen::Quaterniond DeltaQ(const Vec3& phi) {
  const double half = 0.5 * phi.norm();
  const Vec3 xyz = Sinc(half) * 0.5 * phi;
  return Eigen::Quaterniond(std::cos(half), xyz.x(), xyz.y(), xyz.z());
}

/// The right Jacobian of SO(3) (the note's J_r; Forster et al. 2015, eq. 8), by its
/// second-order series below |phi| = 1e-4 as OKVIS evaluates it.
Mat3 RightJacobian(const Vec3& phi) {
  const double angle = phi.norm();
  const Mat3 phi_x = so3::skew(phi);
  const Mat3 phi_x2 = phi_x * phi_x;
  if (angle < 1e-4) return Mat3::Identity() - 0.5 * phi_x + phi_x2 / 6.0;
  const double angle2 = angle * angle;
  return Mat3::Identity() - (1.0 - std::cos(angle)) / angle2 * phi_x +
         (angle - std::sin(angle)) / (angle2 * angle) * phi_x2;
}

/// Left and right multiplication matrices of Hamilton quaternions on coefficient vectors
/// [x y z w]: a (x) b = LeftProductMatrix(a) b = RightProductMatrix(b) a.
Mat4 LeftProductMatrix(const Eigen::Quaterniond& a) {
  const double x = a.x(), y = a.y(), z = a.z(), w = a.w();
  Mat4 m;
  m << w, -z, y, x,  //
      z, w, -x, y,   //
      -y, x, w, z,   //
      -x, -y, -z, w;
  return m;
}
Mat4 RightProductMatrix(const Eigen::Quaterniond& b) {
  const double x = b.x(), y = b.y(), z = b.z(), w = b.w();
  Mat4 m;
  m << w, z, -y, x,  //
      -z, w, x, y,   //
      y, -x, w, z,   //
      -x, -y, -z, w;
  return m;
}

/// The 6x7 map from a Ceres pose block's tangent [x y z qx qy qz qw] to PoseManifold's
/// minimal increment [dr, dalpha] (PoseManifold::minusJacobian): dalpha = 2 vec(dq (x) q^-1),
/// with the block's quaternion as given (conjugated, not normalized, as upstream does).
Eigen::Matrix<double, 6, 7> PoseLift(const Eigen::Quaterniond& q) {
  Eigen::Matrix<double, 6, 7> lift = Eigen::Matrix<double, 6, 7>::Zero();
  lift.topLeftCorner<3, 3>().setIdentity();
  lift.bottomRightCorner<3, 4>() = 2.0 * RightProductMatrix(q.conjugate()).topRows<3>();
  return lift;
}

/// One pass over the samples, shared by propagation and redoPreintegration (they differ in
/// the d alpha/d bg sum and in the noise of a saturated step): the preintegrated sums as
/// ImuError holds them, the rotation sensitivity `cross` they are built from, the increment's
/// covariance before symmetrization, and the summed dt.
struct RunningSums {
  Okvis2Preintegration sums;
  Mat3 cross = Mat3::Zero();
  Mat15 P = Mat15::Zero();
  double Delta_t = 0.0;
};

enum class Pass { kPropagation, kPreintegration };

bool Exceeds(const Vec3& a, const Vec3& b, double limit) {
  return (a.array().abs() > limit).any() || (b.array().abs() > limit).any();
}

Status CheckSpan(const std::vector<Okvis2Sample>& samples, std::int64_t t0, std::int64_t t1,
                 const char* what) {
  if (samples.size() < 2) return Status::Error(std::string(what) + ": needs at least two samples");
  for (std::size_t k = 1; k < samples.size(); ++k) {
    if (samples[k].t_ns <= samples[k - 1].t_ns)
      return Status::Error(std::string(what) + ": sample " + std::to_string(k) +
                           "'s stamp is not after the previous one's");
  }
  for (const Okvis2Sample& s : samples) {
    if (!s.gyro.allFinite() || !s.accel.allFinite())
      return Status::Error(std::string(what) + ": a sample is not finite");
  }
  if (!(t0 < t1)) return Status::Error(std::string(what) + ": the interval is empty or reversed");
  if (samples.front().t_ns > t0 || samples.back().t_ns < t1)
    return Status::Error(std::string(what) + ": the samples do not cover the interval");
  return Status::Ok();
}

/// One pass of OKVIS's loop over [t0, t1] at the biases bg, ba. The noise of each step is
/// added to P with the densities' squares (OKVIS keeps one matrix per density and weights
/// them at the end; the sum is linear in them, so one matrix holds the same numbers).
void Integrate(const std::vector<Okvis2Sample>& samples, const Okvis2ImuParameters& params,
               const Vec3& bg, const Vec3& ba, std::int64_t t0, std::int64_t t1, Pass pass,
               Okvis2Transition transition, RunningSums& s) {
  std::int64_t time = t0;
  bool started = false;
  for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
    Vec3 w0 = samples[k].gyro, a0 = samples[k].accel;
    Vec3 w1 = samples[k + 1].gyro, a1 = samples[k + 1].accel;
    std::int64_t next = samples[k + 1].t_ns;
    double dt = Okvis2Seconds(next - time);
    if (t1 < next) {  // the last step ends inside (t_k, t_k+1]: interpolate its end sample
      const double interval = Okvis2Seconds(next - samples[k].t_ns);
      next = t1;
      dt = Okvis2Seconds(next - time);
      const double r = dt / interval;
      w1 = ((1.0 - r) * w0 + r * w1).eval();
      a1 = ((1.0 - r) * a0 + r * a1).eval();
    }
    if (dt <= 0.0) continue;
    s.Delta_t += dt;
    if (!started) {  // the first step starts inside [t_k, t_k+1): interpolate its start sample
      started = true;
      const double r = dt / Okvis2Seconds(next - samples[k].t_ns);
      w0 = (r * w0 + (1.0 - r) * w1).eval();
      a0 = (r * a0 + (1.0 - r) * a1).eval();
    }
    const bool gyro_saturated = Exceeds(w0, w1, params.g_max);
    const bool accel_saturated = Exceeds(a0, a1, params.a_max);

    const Vec3 w = 0.5 * (w0 + w1) - bg;
    const Vec3 a = 0.5 * (a0 + a1) - ba;
    const Eigen::Quaterniond dq = DeltaQ(w * dt);
    const Eigen::Quaterniond Delta_q_1 = s.sums.Delta_q * dq;
    const Mat3 C = s.sums.Delta_q.toRotationMatrix();
    const Mat3 C_1 = Delta_q_1.toRotationMatrix();
    const Mat3 C_mean_dt = 0.5 * (C + C_1) * dt;  // the step's trapezoid of the rotation
    const Mat3 C_integral_1 = s.sums.C_integral + C_mean_dt;
    const Vec3 acc_integral_1 = s.sums.acc_integral + C_mean_dt * a;
    s.sums.C_doubleintegral += s.sums.C_integral * dt + 0.25 * (C + C_1) * dt * dt;
    s.sums.acc_doubleintegral += s.sums.acc_integral * dt + 0.25 * (C + C_1) * a * dt * dt;

    const Mat3 Jr_dt = RightJacobian(w * dt) * dt;
    s.sums.dalpha_db_g += pass == Pass::kPropagation ? Mat3(dt * C_1) : Mat3(C_1 * Jr_dt);
    const Mat3 cross_1 = dq.inverse().toRotationMatrix() * s.cross + Jr_dt;
    const Mat3 a_x = so3::skew(a);
    const Mat3 bias_lever = C * a_x * s.cross + C_1 * a_x * cross_1;
    const Mat3 dv_db_g_1 = s.sums.dv_db_g + 0.5 * dt * bias_lever;
    s.sums.dp_db_g += dt * s.sums.dv_db_g + 0.25 * dt * dt * bias_lever;

    // The step's transition, order [p, alpha, v, bg, ba] (see the header on its blocks).
    Mat15 F = Mat15::Identity();
    F.block<3, 3>(3, 9) = -dt * C_1;
    F.block<3, 3>(0, 6) = Mat3::Identity() * dt;
    F.block<3, 3>(6, 3) = -so3::skew(0.5 * (C + C_1) * a * dt);
    F.block<3, 3>(6, 12) = -0.5 * (C + C_1) * dt;
    if (transition == Okvis2Transition::kAsOkvis) {
      F.block<3, 3>(0, 3) = -so3::skew(s.sums.acc_integral * dt + 0.25 * (C + C_1) * a * dt * dt);
      F.block<3, 3>(0, 9) = dt * s.sums.dv_db_g + 0.25 * dt * dt * bias_lever;
      F.block<3, 3>(0, 12) = -s.sums.C_integral * dt + 0.25 * (C + C_1) * dt * dt;
      F.block<3, 3>(6, 9) = 0.5 * dt * bias_lever;
    } else {
      // Step-local: the increment's own position and velocity errors carry what came
      // before the step; the bias enters only through this step's rotation and acceleration.
      const Mat3 step_lever = C_1 * a_x * Jr_dt;
      F.block<3, 3>(0, 3) = -so3::skew(0.25 * (C + C_1) * a * dt * dt);
      F.block<3, 3>(0, 9) = 0.25 * dt * dt * step_lever;
      F.block<3, 3>(0, 12) = -0.25 * (C + C_1) * dt * dt;
      F.block<3, 3>(6, 9) = 0.5 * dt * step_lever;
    }
    s.P = (F * s.P * F.transpose()).eval();

    const double gyro_mult = gyro_saturated ? 100.0 : 1.0;
    const double accel_mult = accel_saturated ? 100.0 : 1.0;
    const double sg2 = params.sigma_g_c * params.sigma_g_c;
    const double sa2 = params.sigma_a_c * params.sigma_a_c;
    double var_alpha, var_v, var_p;
    if (pass == Pass::kPropagation) {
      // Upstream scales sigma_g_c by 100 (variance x 1e4) but multiplies the velocity
      // variance by the scaled sigma_a_c only once (x 100).
      var_alpha = dt * sg2 * gyro_mult * gyro_mult;
      var_v = dt * sa2 * accel_mult;
      var_p = 0.5 * dt * dt * var_v;
    } else {
      // redoPreintegration's weights: dt for alpha and v, dt^3/2 for p, times the
      // saturation factor (once for alpha and v, cubed for p).
      var_alpha = gyro_mult * dt * sg2;
      var_v = accel_mult * dt * sa2;
      var_p = 0.5 * dt * dt * dt * accel_mult * accel_mult * accel_mult * sa2;
    }
    const double var_bg = dt * params.sigma_gw_c * params.sigma_gw_c;
    const double var_ba = dt * params.sigma_aw_c * params.sigma_aw_c;
    for (int i = 0; i < 3; ++i) {
      s.P(i, i) += var_p;
      s.P(3 + i, 3 + i) += var_alpha;
      s.P(6 + i, 6 + i) += var_v;
      s.P(9 + i, 9 + i) += var_bg;
      s.P(12 + i, 12 + i) += var_ba;
    }

    s.sums.Delta_q = Delta_q_1;
    s.sums.C_integral = C_integral_1;
    s.sums.acc_integral = acc_integral_1;
    s.cross = cross_1;
    s.sums.dv_db_g = dv_db_g_1;
    time = next;
    ++s.sums.steps;
    if (next == t1) break;
  }
}

}  // namespace

Status Okvis2TimeFromSeconds(double t, std::int64_t& t_ns) {
  if (!std::isfinite(t) || t < 0.0 || t >= 4294967296.0)
    return Status::Error("an OKVIS time stamp must be finite and within 0 .. 2^32 s, got " +
                         std::to_string(t));
  const double sec = std::floor(t);
  const double nsec = std::round((t - sec) * 1e9);
  t_ns = static_cast<std::int64_t>(sec) * kNanosecondsPerSecond + static_cast<std::int64_t>(nsec);
  return Status::Ok();
}

double Okvis2Seconds(std::int64_t duration_ns) {
  // Duration normalizes to whole seconds and 0 <= nanoseconds < 1e9.
  std::int64_t sec = duration_ns / kNanosecondsPerSecond;
  std::int64_t nsec = duration_ns % kNanosecondsPerSecond;
  if (nsec < 0) {
    nsec += kNanosecondsPerSecond;
    --sec;
  }
  return static_cast<double>(sec) + 1e-9 * static_cast<double>(nsec);
}

Status PropagateOkvis2(const std::vector<Okvis2Sample>& samples, const Okvis2ImuParameters& params,
                       const Okvis2State& start, std::int64_t t_start_ns, std::int64_t t_end_ns,
                       Okvis2Propagation& out, Okvis2Transition transition) {
  if (Status st = CheckSpan(samples, t_start_ns, t_end_ns, "OKVIS2 propagation"); !st.ok())
    return st;
  RunningSums s;
  Integrate(samples, params, start.bg, start.ba, t_start_ns, t_end_ns, Pass::kPropagation,
            transition, s);
  const Mat3 C_WS_0 = start.q.normalized().toRotationMatrix();
  const Vec3 g_W(0.0, 0.0, params.g);
  out.steps = s.sums.steps;
  out.Delta_t = s.Delta_t;
  out.end = start;
  out.end.r = start.r + start.v * s.Delta_t + C_WS_0 * s.sums.acc_doubleintegral -
              0.5 * g_W * s.Delta_t * s.Delta_t;
  out.end.q = (start.q.normalized() * s.sums.Delta_q).normalized();
  out.end.v = start.v + C_WS_0 * s.sums.acc_integral - g_W * s.Delta_t;

  Mat15& F = out.jacobian;
  F.setIdentity();
  F.block<3, 3>(0, 3) = -so3::skew(C_WS_0 * s.sums.acc_doubleintegral);
  F.block<3, 3>(0, 6) = Mat3::Identity() * s.Delta_t;
  F.block<3, 3>(0, 9) = C_WS_0 * s.sums.dp_db_g;
  F.block<3, 3>(0, 12) = -C_WS_0 * s.sums.C_doubleintegral;
  F.block<3, 3>(3, 9) = -C_WS_0 * s.sums.dalpha_db_g;
  F.block<3, 3>(6, 3) = -so3::skew(C_WS_0 * s.sums.acc_integral);
  F.block<3, 3>(6, 9) = C_WS_0 * s.sums.dv_db_g;
  F.block<3, 3>(6, 12) = -C_WS_0 * s.sums.C_integral;

  Mat15 T = Mat15::Identity();  // increments in S0 -> errors of the world-frame state
  for (int b = 0; b < 3; ++b) T.block<3, 3>(3 * b, 3 * b) = C_WS_0;
  out.covariance = T * s.P * T.transpose();
  return Status::Ok();
}

Status PreintegrateOkvis2(const std::vector<Okvis2Sample>& samples,
                          const Okvis2ImuParameters& params, const Vec3& bg, const Vec3& ba,
                          std::int64_t t0_ns, std::int64_t t1_ns, Okvis2Preintegration& out,
                          Okvis2Transition transition) {
  if (Status st = CheckSpan(samples, t0_ns, t1_ns, "OKVIS2 preintegration"); !st.ok()) return st;
  RunningSums s;
  Integrate(samples, params, bg, ba, t0_ns, t1_ns, Pass::kPreintegration, transition, s);
  out = s.sums;
  out.bg_ref = bg;
  out.ba_ref = ba;
  out.P_delta = 0.5 * s.P + 0.5 * s.P.transpose();
  Okvis2Information(out.P_delta, out.information);
  return Status::Ok();
}

void Okvis2Information(const Mat15& P_delta, Mat15& information) {
  // OKVIS's pseudo-inverse: eigenvalues above eps * max(1, 15 * largest) inverted, the
  // others replaced by that floor's inverse (PseudoInverse::symmSqrtU; information = U^T U).
  const Eigen::SelfAdjointEigenSolver<Mat15> eig(P_delta);
  const double eps = std::numeric_limits<double>::epsilon();
  const double floor = std::max(eps, eps * 15.0 * eig.eigenvalues().maxCoeff());
  const Eigen::Array<double, 15, 1> inverse =
      (eig.eigenvalues().array() > floor).select(eig.eigenvalues().array().inverse(), 1.0 / floor);
  // Assigned, not returned: Eigen then evaluates the product through a temporary, as it did
  // when this was inline in PreintegrateOkvis2 (returned, the product rounds differently in
  // the last bit, and `refcase --anchor okvis2` outputs would change).
  information = eig.eigenvectors() * inverse.matrix().asDiagonal() * eig.eigenvectors().transpose();
}

bool Okvis2RedoesPreintegration(const Okvis2Preintegration& pre, const Vec3& bg_0,
                                std::size_t n_samples) {
  return pre.steps == 0 || ((bg_0 - pre.bg_ref).norm() > 0.0003 && n_samples < 50);
}

Okvis2ImuErrorTerms EvaluateOkvis2ImuError(const Okvis2Preintegration& pre,
                                           const Okvis2ImuParameters& params, double Delta_t,
                                           const Okvis2State& state_0, const Okvis2State& state_1) {
  const Eigen::Quaterniond q_0 = state_0.q.normalized(), q_1 = state_1.q.normalized();
  const Mat3 C_S0_W = q_0.toRotationMatrix().transpose();
  const Vec3 g_W(0.0, 0.0, params.g);
  Eigen::Matrix<double, 6, 1> Delta_b;
  Delta_b << state_0.bg - pre.bg_ref, state_0.ba - pre.ba_ref;

  const Vec3 delta_p_W =
      state_0.r - state_1.r + state_0.v * Delta_t - 0.5 * g_W * Delta_t * Delta_t;
  const Vec3 delta_v_W = state_0.v - state_1.v - g_W * Delta_t;
  const Eigen::Quaterniond Dq = DeltaQ(-pre.dalpha_db_g * Delta_b.head<3>()) * pre.Delta_q;

  // d residual / d [r0, alpha0, v0, bg0, ba0] (F0) and / d [r1, alpha1, v1, bg1, ba1] (F1).
  Mat15 F0 = Mat15::Identity();
  F0.block<3, 3>(0, 0) = C_S0_W;
  F0.block<3, 3>(0, 3) = C_S0_W * so3::skew(delta_p_W);
  F0.block<3, 3>(0, 6) = C_S0_W * Delta_t;
  F0.block<3, 3>(0, 9) = pre.dp_db_g;
  F0.block<3, 3>(0, 12) = -pre.C_doubleintegral;
  F0.block<3, 3>(3, 3) =
      (LeftProductMatrix(Dq * q_1.inverse()) * RightProductMatrix(q_0)).topLeftCorner<3, 3>();
  F0.block<3, 3>(3, 9) =
      (RightProductMatrix(q_1.inverse() * q_0) * RightProductMatrix(Dq)).topLeftCorner<3, 3>() *
      (-pre.dalpha_db_g);
  F0.block<3, 3>(6, 3) = C_S0_W * so3::skew(delta_v_W);
  F0.block<3, 3>(6, 6) = C_S0_W;
  F0.block<3, 3>(6, 9) = pre.dv_db_g;
  F0.block<3, 3>(6, 12) = -pre.C_integral;

  Mat15 F1 = -Mat15::Identity();
  F1.block<3, 3>(0, 0) = -C_S0_W;
  F1.block<3, 3>(3, 3) =
      -(LeftProductMatrix(Dq) * RightProductMatrix(q_0) * LeftProductMatrix(q_1.inverse()))
           .topLeftCorner<3, 3>();
  F1.block<3, 3>(6, 6) = -C_S0_W;

  Okvis2ImuErrorTerms t;
  t.residual.segment<3>(0) =
      C_S0_W * delta_p_W + pre.acc_doubleintegral + F0.block<3, 6>(0, 9) * Delta_b;
  t.residual.segment<3>(3) = 2.0 * (Dq * (q_1.inverse() * q_0)).vec();
  t.residual.segment<3>(6) = C_S0_W * delta_v_W + pre.acc_integral + F0.block<3, 6>(6, 9) * Delta_b;
  t.residual.segment<3>(9) = state_0.bg - state_1.bg;
  t.residual.segment<3>(12) = state_0.ba - state_1.ba;

  t.jacobian_pose_0_minimal = F0.block<15, 6>(0, 0);
  t.jacobian_pose_1_minimal = F1.block<15, 6>(0, 0);
  t.jacobian_pose_0 = t.jacobian_pose_0_minimal * PoseLift(state_0.q);
  t.jacobian_pose_1 = t.jacobian_pose_1_minimal * PoseLift(state_1.q);
  t.jacobian_speedbias_0 = F0.block<15, 9>(0, 6);
  t.jacobian_speedbias_1 = F1.block<15, 9>(0, 6);
  return t;
}

}  // namespace imuconv::kernels
