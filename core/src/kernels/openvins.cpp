// OpenVINS's RK4 and ANALYTICAL propagation (see imuconv/kernels/openvins.h for the scheme,
// its transition in the `left` chart and the thresholds kept). Phi and the noise-only
// covariance are accumulated in the block form of left_transition.h, as upstream accumulates
// Phi_summed and Qd_summed; the start covariance enters once at the end.
#include "imuconv/kernels/openvins.h"

#include <cmath>

#include "imuconv/kernels/left_transition.h"
#include "imuconv/so3.h"

namespace imuconv::kernels {

namespace {

// Below this |w| (rad/s) compute_Xi_sum uses its first-order forms: half a degree per second,
// formed as upstream forms it so that the bound is the same double.
constexpr double kPi = 3.141592653589793238462643383279502884;
constexpr double kSmallRate = 1.0 / 180 * kPi / 2;
// Below this |w| the rotation axis is taken as zero (compute_Xi_sum's k_hat).
constexpr double kNoAxis = 1e-12;
// Below this |w dt| OpenVINS's Jl_so3 returns the identity.
constexpr double kJlIdentityBelow = 1e-6;

// A JPL quaternion [x, y, z, w] (Trawny and Roumeliotis): q (x) p = L(q) p with the vector
// part's cross product entering with a minus sign, and C(q) = R_GtoI.
using JplQuat = Eigen::Vector4d;

// Omega(w) q: [-w x q_v + q_4 w; -w . q_v], the rate of q_GtoI for the body rate w is Omega(w) q
// / 2.
JplQuat OmegaTimes(const Vec3& w, const JplQuat& q) {
  JplQuat r;
  r.head<3>() = q[3] * w - w.cross(q.head<3>());
  r[3] = -w.dot(q.head<3>());
  return r;
}

// quatnorm: unit norm with a non-negative scalar part.
JplQuat Normalized(const JplQuat& q) { return (q[3] < 0.0 ? -q : q) / q.norm(); }

// C(q) = (2 q_4^2 - 1) I - 2 q_4 [q_v]x + 2 q_v q_v^T (Trawny eq. 62).
Mat3 JplRotation(const JplQuat& q) {
  const Vec3 qv = q.head<3>();
  Mat3 C = (2.0 * q[3] * q[3] - 1.0) * Mat3::Identity() - (2.0 * q[3]) * so3::skew(qv);
  C.noalias() += 2.0 * qv * qv.transpose();
  return C;
}

// Jl(phi) = sin t/t I + (1 - sin t/t) u u^T + (1 - cos t)/t [u]x, t = |phi|, u = phi/t,
// as OpenVINS's Jl_so3 computes it (the identity below t = 1e-6).
Mat3 OpenVinsJl(const Vec3& phi) {
  const double t = phi.norm();
  if (t < kJlIdentityBelow) return Mat3::Identity();
  const Vec3 u = phi / t;
  const double sinc = std::sin(t) / t;
  Mat3 J = sinc * Mat3::Identity() + ((1.0 - std::cos(t)) / t) * so3::skew(u);
  J.noalias() += (1.0 - sinc) * u * u.transpose();
  return J;
}

struct Knot {
  Vec3 w, a;  // bias-corrected
};

// predict_mean_rk4: RK4 on (dq, p, v) from the interval's start with w, a linear in time.
// R, p, v are the state at t_k and are replaced by the state at t_k+1.
void Rk4Mean(const Knot& k1, const Knot& k2, double dt, const Vec3& gravity, Mat3& R, Vec3& p,
             Vec3& v) {
  const Vec3 w_rate = (k2.w - k1.w) / dt, a_rate = (k2.a - k1.a) / dt;
  const JplQuat dq0(0.0, 0.0, 0.0, 1.0);
  // The world acceleration at a stage: R_GtoI of the stage is C(dq) C(q_k), so its transpose
  // applied to a is R C(dq)^T a.
  auto accel = [&](const JplQuat& dq, const Vec3& a) -> Vec3 {
    return R * (JplRotation(dq).transpose() * a) + gravity;
  };

  Vec3 w = k1.w, a = k1.a;
  const JplQuat kq1 = (0.5 * dt) * OmegaTimes(w, dq0);
  const Vec3 kp1 = dt * v, kv1 = dt * (R * a + gravity);  // C(dq0) = I

  w += (0.5 * dt) * w_rate;
  a += (0.5 * dt) * a_rate;
  const JplQuat dq1 = Normalized(dq0 + 0.5 * kq1);
  const Vec3 v1 = v + 0.5 * kv1;
  const JplQuat kq2 = (0.5 * dt) * OmegaTimes(w, dq1);
  const Vec3 kp2 = dt * v1, kv2 = dt * accel(dq1, a);

  const JplQuat dq2 = Normalized(dq0 + 0.5 * kq2);
  const Vec3 v2 = v + 0.5 * kv2;
  const JplQuat kq3 = (0.5 * dt) * OmegaTimes(w, dq2);
  const Vec3 kp3 = dt * v2, kv3 = dt * accel(dq2, a);

  w += (0.5 * dt) * w_rate;
  a += (0.5 * dt) * a_rate;
  const JplQuat dq3 = Normalized(dq0 + kq3);
  const Vec3 v3 = v + kv3;
  const JplQuat kq4 = (0.5 * dt) * OmegaTimes(w, dq3);
  const Vec3 kp4 = dt * v3, kv4 = dt * accel(dq3, a);

  constexpr double kSixth = 1.0 / 6.0, kThird = 1.0 / 3.0;
  const JplQuat dq = Normalized(dq0 + kSixth * kq1 + kThird * kq2 + kThird * kq3 + kSixth * kq4);
  p += kSixth * kp1 + kThird * kp2 + kThird * kp3 + kSixth * kp4;
  v += kSixth * kv1 + kThird * kv2 + kThird * kv3 + kSixth * kv4;
  R = R * JplRotation(dq).transpose();  // Eigen evaluates the product into a temporary
}

// P <- T P T^T for a step in block form: Congruence (left_transition.h), with its 15x3 by 3x3
// products written as axpys of whole columns (common.h), which Eigen's generic small-product
// path neither inlines nor vectorises; half the time of a step went there.
void CongruenceStep(const LeftTransition& T, Mat15& P) {
  constexpr int kP = left_idx::p, kTh = left_idx::theta, kV = left_idx::v, kBg = left_idx::bg,
                kBa = left_idx::ba;
  // C = P E^T, non-zero in the p, theta and v columns only (E = T - I).
  Eigen::Matrix<double, 15, 9> C;
  AssignTimes3x3(P.middleCols<3>(kTh), T.p_th.transpose(), C.middleCols<3>(kP));
  C.middleCols<3>(kP) += T.p_v * P.middleCols<3>(kV);
  AddTimes3x3(P.middleCols<3>(kBg), T.p_bg.transpose(), C.middleCols<3>(kP));
  AddTimes3x3(P.middleCols<3>(kBa), T.p_ba.transpose(), C.middleCols<3>(kP));
  AssignTimes3x3(P.middleCols<3>(kBg), T.th_bg.transpose(), C.middleCols<3>(kTh));
  AssignTimes3x3(P.middleCols<3>(kTh), T.v_th.transpose(), C.middleCols<3>(kV));
  AddTimes3x3(P.middleCols<3>(kBg), T.v_bg.transpose(), C.middleCols<3>(kV));
  AddTimes3x3(P.middleCols<3>(kBa), T.v_ba.transpose(), C.middleCols<3>(kV));
  // E C = E P E^T, 9x9; its rows from 3x3 blocks of E and 3x9 row blocks of C.
  Mat9 EC;
  EC.middleRows<3>(kP).noalias() = T.p_th.lazyProduct(C.middleRows<3>(kTh));
  EC.middleRows<3>(kP) += T.p_v * C.middleRows<3>(kV);
  EC.middleRows<3>(kP).noalias() += T.p_bg.lazyProduct(C.middleRows<3>(kBg));
  EC.middleRows<3>(kP).noalias() += T.p_ba.lazyProduct(C.middleRows<3>(kBa));
  EC.middleRows<3>(kTh).noalias() = T.th_bg.lazyProduct(C.middleRows<3>(kBg));
  EC.middleRows<3>(kV).noalias() = T.v_th.lazyProduct(C.middleRows<3>(kTh));
  EC.middleRows<3>(kV).noalias() += T.v_bg.lazyProduct(C.middleRows<3>(kBg));
  EC.middleRows<3>(kV).noalias() += T.v_ba.lazyProduct(C.middleRows<3>(kBa));
  // T P T^T = P + C + C^T + E C.
  P.leftCols<9>() += C;
  P.topRows<9>() += C.transpose();
  P.topLeftCorner<9, 9>() += EC;
}

}  // namespace

void OpenVinsIntegralsOf(double dt, const Vec3& w, const Vec3& a, bool derivatives,
                         OpenVinsIntegrals& xi) {
  const double rate = w.norm(), th = rate * dt;
  const Vec3 axis = rate > kNoAxis ? Vec3(w / rate) : Vec3::Zero();
  const Mat3 I = Mat3::Identity(), K = so3::skew(axis), K2 = K * K, A = so3::skew(a);
  const double dt2 = dt * dt, dt3 = dt2 * dt, c = std::cos(th), s = std::sin(th);
  const double ka = axis.dot(a);
  if (rate >= kSmallRate) {
    const double rate2 = rate * rate, rate3 = rate2 * rate, th2 = th * th, th3 = th2 * th;
    xi.Xi1 = dt * I + ((1.0 - c) / rate) * K + (dt - s / rate) * K2;
    xi.Xi2 = (0.5 * dt2) * I + ((th - s) / rate2) * K + (0.5 * dt2 - (1.0 - c) / rate2) * K2;
    if (derivatives) {
      const Mat3 AK = A * K, KA = K * A, AK2 = A * K2, K2A_plus = K2 * A + ka * K;
      xi.Xi3 = (0.5 * dt2) * A + ((s - th) / rate2) * AK + ((s - th * c) / rate2) * KA +
               (0.5 * dt2 - (1.0 - c) / rate2) * AK2 +
               (0.5 * dt2 + (1.0 - c - th * s) / rate2) * K2A_plus -
               ((3.0 * s - 2.0 * th - th * c) / rate2 * ka) * K2;
      xi.Xi4 = (dt3 / 6.0) * A + ((2.0 * (1.0 - c) - th2) / (2.0 * rate3)) * AK +
               ((2.0 * (1.0 - c) - th * s) / rate3) * KA + ((s - th) / rate3 + dt3 / 6.0) * AK2 +
               ((th - 2.0 * s + th3 / 6.0 + th * c) / rate3) * K2A_plus +
               ((4.0 * c - 4.0 + th2 + th * s) / rate3 * ka) * K2;
    }
  } else {
    // OpenVINS's forms for a slow rotation (see the header): not the integrals themselves.
    xi.Xi1 = dt * (I + s * K + (1.0 - c) * K2);
    xi.Xi2 = (0.5 * dt) * xi.Xi1;
    if (derivatives) {
      xi.Xi3 = (0.5 * dt2) *
               (A + s * (K * A - A * K + ka * K2) + (1.0 - c) * (A * K2 + K2 * A + ka * K));
      xi.Xi4 = (dt / 3.0) * xi.Xi3;
    }
  }
  if (derivatives) xi.Jl = OpenVinsJl(w * dt);
}

Status PropagateOpenVins(const PropagationInput& in, OpenVinsMean mean, PropagationResult& out,
                         Outputs outputs) {
  if (Status st = CheckPropagationInput(in); !st.ok()) return st;
  const bool want_phi = WantsTransition(outputs), want_cov = WantsCovariance(outputs);
  const bool derivatives = want_phi || want_cov;
  const SampleWindow& win = in.window;
  const NoiseVariances q(in.noise);
  const Vec3& g = in.gravity;
  const Vec3 bias_g = in.x_s.bg, bias_a = in.x_s.ba;

  Mat3 R = in.x_s.R;
  Vec3 p = in.x_s.p, v = in.x_s.v;
  LeftTransition Phi, F;
  Mat15 Qd = Mat15::Zero();  // Qd_summed, the noise alone
  OpenVinsIntegrals xi;
  Knot k1{win[0].gyro - bias_g, win[0].accel - bias_a};
  for (std::size_t j = 0; j + 1 < win.size(); ++j) {
    const ImuSample& s2 = win[j + 1];
    const Knot k2{s2.gyro - bias_g, s2.accel - bias_a};
    const double dt = s2.t - win[j].t;
    const Vec3 w_mean = 0.5 * (k1.w + k2.w), a_mean = 0.5 * (k1.a + k2.a);
    // RK4's mean does not use the integrals; the analytical one needs Xi1 and Xi2.
    if (derivatives || mean == OpenVinsMean::kAnalytical)
      OpenVinsIntegralsOf(dt, w_mean, a_mean, derivatives, xi);

    const Mat3 R_k = R;
    const Vec3 p_k = p, v_k = v;
    if (mean == OpenVinsMean::kAnalytical) {
      R = R_k * so3::Exp(dt * w_mean);
      v = v_k + R_k * (xi.Xi1 * a_mean) + dt * g;
      p = p_k + dt * v_k + R_k * (xi.Xi2 * a_mean) + (0.5 * dt * dt) * g;
    } else {
      Rk4Mean(k1, k2, dt, g, R, p, v);
    }

    if (derivatives) {
      // compute_F_and_G_analytic's F in the left chart (header); its G is F's bias columns
      // without the identity for the measurement noise, dt I for the random walks.
      F.th_bg.noalias() = -dt * (R_k * xi.Jl);
      F.p_th = -so3::skew(p - p_k - dt * v_k - (0.5 * dt * dt) * g);
      F.v_th = -so3::skew(v - v_k - dt * g);
      F.p_v = dt;
      F.p_bg.noalias() = R_k * xi.Xi4;
      F.v_bg.noalias() = R_k * xi.Xi3;
      F.p_ba.noalias() = -R_k * xi.Xi2;
      F.v_ba.noalias() = -R_k * xi.Xi1;
      if (want_phi) Phi.PrependStep(F);
      if (want_cov) {
        CongruenceStep(F, Qd);
        Eigen::Matrix<double, 9, 3> G_g, G_a;  // rows p, theta, v
        G_g << F.p_bg, F.th_bg, F.v_bg;
        G_a << F.p_ba, Mat3::Zero(), F.v_ba;
        Qd.topLeftCorner<9, 9>() += (q.gyro / dt) * G_g.lazyProduct(G_g.transpose());
        Qd.topLeftCorner<9, 9>() += (q.accel / dt) * G_a.lazyProduct(G_a.transpose());
        Qd.block<3, 3>(left_idx::bg, left_idx::bg).diagonal().array() += q.gyro_walk * dt;
        Qd.block<3, 3>(left_idx::ba, left_idx::ba).diagonal().array() += q.accel_walk * dt;
      }
    }
    k1 = k2;
  }

  out.x_e.R = R;
  out.x_e.p = p;
  out.x_e.v = v;
  out.x_e.bg = bias_g;
  out.x_e.ba = bias_a;
  if (want_phi) out.Phi = Phi.ToMatrix();
  if (want_cov) {
    // EKFPropagation: Phi P_s Phi^T + Qd_summed.
    const Mat15 P = Congruence(Phi, in.cov_s) + Qd;
    out.cov = 0.5 * (P + P.transpose());
  }
  return Status::Ok();
}

}  // namespace imuconv::kernels
