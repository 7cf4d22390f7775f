// FAST-LIO2's forward propagation of one scan (imuconv/kernels/fast_lio2.h has the feeding,
// the scheme, the noise interpretation and the error state).
#include "imuconv/kernels/fast_lio2.h"

#include <cmath>
#include <string>

#include "imuconv/kernels/common.h"
#include "imuconv/so3.h"

namespace imuconv::kernels {
namespace {

using Mat32 = Eigen::Matrix<double, 3, 2>;
using Mat23x12 = Eigen::Matrix<double, 23, 12>;

// MTK's threshold below which a rotation vector counts as zero (mtkmath.hpp's tolerance of
// double), used where upstream switches to the small-angle form.
constexpr double kMtkTolerance = 1e-11;

/// The unit quaternion of the rotation by the vector w dt (MTK's SO3::exp(w, dt), whose
/// half-angle is dt |w| / 2).
Eigen::Quaterniond RotationQuaternion(const Vec3& w, double dt) {
  const double half_angle = 0.5 * std::abs(dt) * w.norm();
  // sin(x)/x by its series for x^2 < 1e-8, where the next term (x^6/5040) is below eps
  const double x2 = half_angle * half_angle;
  const double sinc =
      x2 < 1e-8 ? 1.0 - x2 / 6.0 + x2 * x2 / 120.0 : std::sin(half_angle) / half_angle;
  const Vec3 xyz = sinc * (0.5 * dt) * w;
  return Eigen::Quaterniond(std::cos(half_angle), xyz.x(), xyz.y(), xyz.z());
}

/// Log of a unit quaternion (the rotation vector, angle in [0, pi]).
Vec3 RotationVector(Eigen::Quaterniond q) {
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  if (s < kMtkTolerance) return 2.0 * q.vec() / q.w();
  return (2.0 * std::atan2(s, q.w()) / s) * q.vec();
}

/// MTK's A_matrix(v) = I + (1 - cos|v|)/|v|^2 [v]x + (1 - sin|v|/|v|)/|v|^2 [v]x^2: the left
/// Jacobian of SO(3) at v, i.e. the right Jacobian J_r(-v) (the note's J_r).
Mat3 AMatrix(const Vec3& v) {
  const double angle2 = v.squaredNorm();
  const double angle = std::sqrt(angle2);
  if (angle < kMtkTolerance) return Mat3::Identity();
  const Mat3 v_x = so3::skew(v);
  return Mat3::Identity() + (1.0 - std::cos(angle)) / angle2 * v_x +
         (1.0 - std::sin(angle) / angle) / angle2 * v_x * v_x;
}

/// d grav / d delta of the S2 boxplus at delta = 0 (MTK's S2_Mx with a zero delta).
Mat32 S2BoxplusJacobian(const FastLio2Gravity& g) { return -so3::skew(g.vec) * FastLio2S2Basis(g); }

/// d delta / d grav of the S2 boxminus at the point itself (MTK's S2_Nx_yy).
Eigen::Matrix<double, 2, 3> S2BoxminusJacobian(const FastLio2Gravity& g) {
  return 1.0 / g.length / g.length * FastLio2S2Basis(g).transpose() * so3::skew(g.vec);
}

bool Finite(const Vec3& v) { return v.allFinite(); }

constexpr const char* kWhat = "FAST-LIO2 scan propagation";

Status CheckFeeding(const std::vector<ImuSample>& samples, const FastLio2Parameters& params,
                    double last_scan_end, double scan_end) {
  if (samples.size() < 2)
    return Status::Error(std::string(kWhat) + ": needs at least two IMU samples");
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const ImuSample& s = samples[k];
    if (!std::isfinite(s.t) || !Finite(s.gyro) || !Finite(s.accel))
      return Status::Error(std::string(kWhat) + ": sample " + std::to_string(k) + " is not finite");
    if (k > 0 && !(s.t >= samples[k - 1].t))
      return Status::Error(std::string(kWhat) + ": sample " + std::to_string(k) + "'s time " +
                           std::to_string(s.t) + " is before the previous sample's");
  }
  if (!std::isfinite(last_scan_end) || !std::isfinite(scan_end) || !(scan_end >= last_scan_end))
    return Status::Error(std::string(kWhat) + ": the scan's end times are not finite or reversed");
  if (!(samples.back().t >= last_scan_end))
    return Status::Error(std::string(kWhat) +
                         ": no IMU sample at or after the previous scan's end");
  if (!std::isfinite(params.G_m_s2) || !(params.mean_acc_norm > 0.0) ||
      !std::isfinite(params.mean_acc_norm))
    return Status::Error(std::string(kWhat) +
                         ": G_m_s2 must be finite and |mean_acc| positive and finite");
  return Status::Ok();
}

Status CheckStart(const FastLio2Parameters& params, const FastLio2State& start, const Mat23& P0) {
  for (const double c : {params.gyr_cov, params.acc_cov, params.b_gyr_cov, params.b_acc_cov})
    if (!std::isfinite(c) || c < 0.0)
      return Status::Error(std::string(kWhat) + ": a noise covariance is negative or not finite");
  // Length 0 is the no-gravity point (header comment), valid only with the zero vector.
  const bool no_gravity = start.grav.length == 0.0 && start.grav.vec.isZero(0.0);
  if (!(start.grav.length > 0.0 || no_gravity) || !std::isfinite(start.grav.length) ||
      !Finite(start.grav.vec))
    return Status::Error(std::string(kWhat) +
                         ": the gravity's S2 length must be positive and finite (or 0 with a "
                         "zero gravity vector)");
  if (!Finite(start.pos) || !Finite(start.vel) || !Finite(start.bg) || !Finite(start.ba) ||
      !Finite(start.offset_T_L_I) || !start.rot.coeffs().allFinite() ||
      !start.offset_R_L_I.coeffs().allFinite())
    return Status::Error(std::string(kWhat) + ": the start state is not finite");
  if (!P0.allFinite()) return Status::Error(std::string(kWhat) + ": P0 is not finite");
  return Status::Ok();
}

/// F M for a step's transition F (FastLio2StepJacobians) and any M, from F's nonzero blocks
/// only. F is the identity but for the rows of pos (its vel column), rot (rot, bg), vel (rot,
/// ba, grav) and grav (grav); every other row of F M is M's own row, exactly, as in the dense
/// product (1 times an entry plus exact zeros). FAST-LIO's own step is the dense 23x23 product
/// F_x1 * cov * F_x1^T; summing only the nonzero terms gives its numbers to rounding (the terms
/// left out are zeros) at about a tenth of the arithmetic: the hot loop's block sparsity. The
/// 3x23 products are coefficient-based (lazyProduct): at these sizes Eigen would otherwise
/// route them through its blocked general product. `out` must not be M.
void LeftMultiplyByTransition(const Mat23& F, const Mat23& M, Mat23& out) {
  constexpr int pos = kFastLio2Pos, rot = kFastLio2Rot, vel = kFastLio2Vel, bg = kFastLio2Bg,
                ba = kFastLio2Ba, grav = kFastLio2Grav;
  out = M;
  out.middleRows<3>(pos).noalias() += F.block<3, 3>(pos, vel).lazyProduct(M.middleRows<3>(vel));
  out.middleRows<3>(rot).noalias() = F.block<3, 3>(rot, rot).lazyProduct(M.middleRows<3>(rot)) +
                                     F.block<3, 3>(rot, bg).lazyProduct(M.middleRows<3>(bg));
  out.middleRows<3>(vel).noalias() += F.block<3, 3>(vel, rot).lazyProduct(M.middleRows<3>(rot)) +
                                      F.block<3, 3>(vel, ba).lazyProduct(M.middleRows<3>(ba)) +
                                      F.block<3, 2>(vel, grav).lazyProduct(M.middleRows<2>(grav));
  out.middleRows<2>(grav).noalias() = F.block<2, 2>(grav, grav).lazyProduct(M.middleRows<2>(grav));
}

/// F M F^T, as (F (F M)^T)^T: the same products as the dense (F M) F^T, term for term, without
/// assuming M symmetric.
void CongruenceByTransition(const Mat23& F, Mat23& M) {
  Mat23 FM, FMFt_transposed;
  LeftMultiplyByTransition(F, M, FM);
  const Mat23 FM_transposed = FM.transpose();
  LeftMultiplyByTransition(F, FM_transposed, FMFt_transposed);
  M = FMFt_transposed.transpose();
}

/// dt G diag(q) dt G^T for FastLio2StepJacobians' dt G, whose noise columns each reach one
/// block of rows (ng: rot, na: vel, nbg: bg, nba: ba): block diagonal, each block the dense
/// product's own terms.
Mat23 StepNoise(const Eigen::Matrix<double, 23, 12>& dt_G, const double q_diag[4]) {
  Mat23 noise = Mat23::Zero();
  const int rows[4] = {kFastLio2Rot, kFastLio2Vel, kFastLio2Bg, kFastLio2Ba};
  for (int b = 0; b < 4; ++b) {
    const Mat3 G = dt_G.block<3, 3>(rows[b], 3 * b);
    noise.block<3, 3>(rows[b], rows[b]).noalias() = (G * q_diag[b]).lazyProduct(G.transpose());
  }
  return noise;
}

/// One predict of the covariances and the transition product (F computed once for all).
void PredictCovariances(const FastLio2State& x, const FastLio2Input& in, double dt,
                        double q_diag[4], FastLio2Transition transition, FastLio2Propagation& out) {
  Mat23 F;
  Mat23x12 dt_G;
  FastLio2StepJacobians(x, in, dt, transition, F, dt_G);
  const Mat23 noise = StepNoise(dt_G, q_diag);
  CongruenceByTransition(F, out.covariance);
  out.covariance += noise;
  CongruenceByTransition(F, out.Qd_summed);
  out.Qd_summed += noise;
  const Mat23 Phi = out.Phi_summed;
  LeftMultiplyByTransition(F, Phi, out.Phi_summed);
}

}  // namespace

FastLio2Gravity FastLio2GravityAsBuilt(const Vec3& g) {
  FastLio2Gravity s;
  s.length = 98090.0 / 10000.0;  // S2<double, 98090, 10000, 1>: den / num
  s.vec = g.normalized() * s.length;
  return s;
}

FastLio2Gravity FastLio2GravityExact(const Vec3& g) {
  FastLio2Gravity s;
  s.vec = g;
  s.length = g.norm();
  return s;
}

Eigen::Matrix<double, 3, 2> FastLio2S2Basis(const FastLio2Gravity& g) {
  // Type 1: the basis that maps the first axis' tangent plane to that of vec by the rotation
  // about their common normal (singular only at vec = -length e_x, where a fixed one is used).
  const Vec3& v = g.vec;
  const double L = g.length;
  Mat32 B;
  if (v.x() + L > kMtkTolerance) {
    const double c = 1.0 / (L + v.x());
    B << -v.y(), -v.z(),                            //
        L - v.y() * v.y() * c, -v.z() * v.y() * c,  //
        -v.z() * v.y() * c, L - v.z() * v.z() * c;
    B /= L;
  } else {
    B << 0.0, 0.0, 0.0, -1.0, 1.0, 0.0;
  }
  return B;
}

FastLio2State FastLio2Boxplus(const FastLio2State& x, const Vec23& d) {
  FastLio2State y = x;
  y.pos += d.segment<3>(kFastLio2Pos);
  y.rot = x.rot * RotationQuaternion(d.segment<3>(kFastLio2Rot), 1.0);
  y.offset_R_L_I = x.offset_R_L_I * RotationQuaternion(d.segment<3>(kFastLio2OffsetR), 1.0);
  y.offset_T_L_I += d.segment<3>(kFastLio2OffsetT);
  y.vel += d.segment<3>(kFastLio2Vel);
  y.bg += d.segment<3>(kFastLio2Bg);
  y.ba += d.segment<3>(kFastLio2Ba);
  const Vec3 tangent = FastLio2S2Basis(x.grav) * d.segment<2>(kFastLio2Grav);
  y.grav.vec = RotationQuaternion(tangent, 1.0).toRotationMatrix() * x.grav.vec;
  return y;
}

Vec23 FastLio2Boxminus(const FastLio2State& y, const FastLio2State& x) {
  Vec23 d;
  d.segment<3>(kFastLio2Pos) = y.pos - x.pos;
  d.segment<3>(kFastLio2Rot) = RotationVector(x.rot.conjugate() * y.rot);
  d.segment<3>(kFastLio2OffsetR) = RotationVector(x.offset_R_L_I.conjugate() * y.offset_R_L_I);
  d.segment<3>(kFastLio2OffsetT) = y.offset_T_L_I - x.offset_T_L_I;
  d.segment<3>(kFastLio2Vel) = y.vel - x.vel;
  d.segment<3>(kFastLio2Bg) = y.bg - x.bg;
  d.segment<3>(kFastLio2Ba) = y.ba - x.ba;
  // The rotation vector taking x's gravity to y's, about their common normal, in x's basis.
  const Vec3 normal = x.grav.vec.cross(y.grav.vec);
  const double sine = normal.norm(), cosine = x.grav.vec.dot(y.grav.vec);
  const Vec3 axis_angle =
      sine < kMtkTolerance ? Vec3::Zero() : Vec3(std::atan2(sine, cosine) / sine * normal);
  d.segment<2>(kFastLio2Grav) = FastLio2S2Basis(x.grav).transpose() * axis_angle;
  return d;
}

FastLio2State FastLio2PredictState(const FastLio2State& x, const FastLio2Input& in, double dt) {
  // f(x, in) from the pre-step state; every block moves by f dt.
  const Vec3 omega = in.gyro - x.bg;
  const Vec3 a_world = x.rot * (in.acc - x.ba);
  FastLio2State y = x;
  y.pos = x.pos + dt * x.vel;
  y.rot = x.rot * RotationQuaternion(omega, dt);
  y.vel = x.vel + dt * (a_world + x.grav.vec);
  return y;
}

void FastLio2StepJacobians(const FastLio2State& x, const FastLio2Input& in, double dt,
                           FastLio2Transition transition, Mat23& F,
                           Eigen::Matrix<double, 23, 12>& dt_G) {
  const Vec3 omega = in.gyro - x.bg;
  const Vec3 acc = in.acc - x.ba;
  const Mat3 R = x.rot.toRotationMatrix();
  // The rotation rows of the continuous Jacobians are mapped through A(-w dt) = J_r(w dt):
  // the derivative of Log(Exp(w dt)^-1 Exp((w + dw) dt)) is J_r(w dt) dw dt.
  const Mat3 Jr = AMatrix(-dt * omega);

  Mat23 f_x = Mat23::Zero();
  f_x.block<3, 3>(kFastLio2Pos, kFastLio2Vel).setIdentity();
  f_x.block<3, 3>(kFastLio2Rot, kFastLio2Bg) = -Jr;
  f_x.block<3, 3>(kFastLio2Vel, kFastLio2Rot) = -R * so3::skew(acc);
  f_x.block<3, 3>(kFastLio2Vel, kFastLio2Ba) = -R;
  f_x.block<3, 2>(kFastLio2Vel, kFastLio2Grav) = S2BoxplusJacobian(x.grav);

  F.setIdentity();
  if (transition == FastLio2Transition::kExactRotation) {
    // d drot_k+1 / d drot_k = Exp(-w dt). Upstream's half-angle 1/2 is the integer 0, which
    // turns this into the identity; the extrinsic rotation's own block is Exp(0) = I anyway.
    F.block<3, 3>(kFastLio2Rot, kFastLio2Rot) = RotationQuaternion(-omega, dt).toRotationMatrix();
  }
  // Gravity does not move: its block is the chart's own N(g) M(g) (the identity to rounding);
  // with no gravity (length 0) that product is 0/0, and its limit, the identity, stays.
  if (x.grav.length > 0.0)
    F.block<2, 2>(kFastLio2Grav, kFastLio2Grav) =
        S2BoxminusJacobian(x.grav) * S2BoxplusJacobian(x.grav);
  F += f_x * dt;

  // Noise [ng, na, nbg, nba]: w = gyro - bg - ng, a = acc - ba - na, bias rates nbg, nba.
  dt_G.setZero();
  dt_G.block<3, 3>(kFastLio2Rot, 0) = -Jr * dt;
  dt_G.block<3, 3>(kFastLio2Vel, 3) = -R * dt;
  dt_G.block<3, 3>(kFastLio2Bg, 6) = Mat3::Identity() * dt;
  dt_G.block<3, 3>(kFastLio2Ba, 9) = Mat3::Identity() * dt;
}

Status FastLio2ScanPredicts(const std::vector<ImuSample>& samples, const FastLio2Parameters& params,
                            double last_scan_end, double scan_end,
                            std::vector<FastLio2Predict>& predicts) {
  predicts.clear();
  const Status valid = CheckFeeding(samples, params, last_scan_end, scan_end);
  if (!valid.ok()) return valid;
  predicts.reserve(samples.size());
  FastLio2Predict p;
  for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
    const ImuSample& head = samples[k];
    const ImuSample& tail = samples[k + 1];
    if (tail.t < last_scan_end) continue;  // a pair wholly before this scan
    p.in.gyro = 0.5 * (head.gyro + tail.gyro);
    // ImuProcess's scaling to G_m_s2 (a factor 1 when |mean_acc| = G_m_s2, still rounded twice).
    p.in.acc = (0.5 * (head.accel + tail.accel)) * params.G_m_s2 / params.mean_acc_norm;
    p.dt = head.t < last_scan_end ? tail.t - last_scan_end : tail.t - head.t;
    predicts.push_back(p);
  }
  // The frame-end predict with the last input: ImuProcess's `note` makes its dt the distance
  // from the last sample to the scan end, with the sign -1 when the scan does not end after it
  // (-0.0 when it ends on the sample: a no-op).
  const double imu_end = samples.back().t;
  const double note = scan_end > imu_end ? 1.0 : -1.0;
  p.dt = note * (scan_end - imu_end);
  predicts.push_back(p);
  return Status::Ok();
}

Status PropagateFastLio2Scan(const std::vector<ImuSample>& samples,
                             const FastLio2Parameters& params, double last_scan_end,
                             double scan_end, const FastLio2State& start, const Mat23& P0,
                             FastLio2Propagation& out, FastLio2Transition transition) {
  const Status valid = CheckStart(params, start, P0);
  if (!valid.ok()) return valid;
  std::vector<FastLio2Predict> predicts;
  const Status fed = FastLio2ScanPredicts(samples, params, last_scan_end, scan_end, predicts);
  if (!fed.ok()) return fed;
  out = FastLio2Propagation();
  out.covariance = P0;
  FastLio2State x = start;
  double q_diag[4] = {params.gyr_cov, params.acc_cov, params.b_gyr_cov, params.b_acc_cov};
  for (const FastLio2Predict& p : predicts) {
    PredictCovariances(x, p.in, p.dt, q_diag, transition, out);
    x = FastLio2PredictState(x, p.in, p.dt);
    ++out.n_predict;
    out.sum_dt += p.dt;
  }
  out.last_predict_dt = predicts.back().dt;
  out.end = x;
  return Status::Ok();
}

namespace {

// The [pos, rot, vel, bg, ba] blocks (convention `fast_lio2`, 15) in the 23-dimensional state.
constexpr int kFifteenIn23[5] = {kFastLio2Pos, kFastLio2Rot, kFastLio2Vel, kFastLio2Bg,
                                 kFastLio2Ba};

Mat23 Embed(const Mat15& m) {
  Mat23 out = Mat23::Zero();
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      out.block<3, 3>(kFifteenIn23[i], kFifteenIn23[j]) = m.block<3, 3>(3 * i, 3 * j);
  return out;
}

/// The window's knots as ImuProcess's samples of one scan (PropagateFastLio2's feeding).
std::vector<ImuSample> Knots(const SampleWindow& win) {
  std::vector<ImuSample> knots(win.size());
  for (std::size_t j = 0; j < win.size(); ++j) knots[j] = win[j];
  return knots;
}

Mat15 Restrict(const Mat23& m) {
  Mat15 out;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      out.block<3, 3>(3 * i, 3 * j) = m.block<3, 3>(kFifteenIn23[i], kFifteenIn23[j]);
  return out;
}

}  // namespace

Status PropagateFastLio2(const PropagationInput& in, FastLio2Transition transition,
                         FastLio2NoiseReading noise, PropagationResult& out) {
  if (Status st = CheckPropagationInput(in); !st.ok()) return st;
  const SampleWindow& win = in.window;
  const std::vector<ImuSample> knots = Knots(win);

  FastLio2Parameters params;  // G_m_s2 = |mean_acc| = 9.81
  const ImuNoise& n = in.noise;
  if (noise == FastLio2NoiseReading::kDensities) {
    const double rate = static_cast<double>(win.size() - 1) / (win.t_end() - win.t_start());
    params.gyr_cov = n.gyro_noise_density * n.gyro_noise_density * rate;
    params.acc_cov = n.accel_noise_density * n.accel_noise_density * rate;
    params.b_gyr_cov = n.gyro_random_walk * n.gyro_random_walk * rate;
    params.b_acc_cov = n.accel_random_walk * n.accel_random_walk * rate;
  } else {
    params.gyr_cov = n.gyro_noise_density;
    params.acc_cov = n.accel_noise_density;
    params.b_gyr_cov = n.gyro_random_walk;
    params.b_acc_cov = n.accel_random_walk;
  }

  FastLio2State start;
  start.pos = in.x_s.p;
  start.rot = Eigen::Quaterniond(in.x_s.R).normalized();
  start.vel = in.x_s.v;
  start.bg = in.x_s.bg;
  start.ba = in.x_s.ba;
  start.grav = FastLio2GravityExact(in.gravity);

  FastLio2Propagation run;
  const Status st = PropagateFastLio2Scan(knots, params, win.t_start(), win.t_end(), start,
                                          Embed(in.cov_s), run, transition);
  if (!st.ok()) return st;
  out.x_e.R = run.end.rot.toRotationMatrix();
  out.x_e.p = run.end.pos;
  out.x_e.v = run.end.vel;
  out.x_e.bg = run.end.bg;
  out.x_e.ba = run.end.ba;
  out.Phi = Restrict(run.Phi_summed);
  out.cov = Restrict(run.covariance);
  return Status::Ok();
}

Status FastLio2IncrementMean(const PreintegrationInput& in, PreintIncrement& delta) {
  delta = PreintIncrement();
  const PropagationInput start =
      PreintegrationByPropagationStart(in.window, in.bg, in.ba, in.noise);
  if (Status st = CheckPropagationInput(start); !st.ok()) return st;
  std::vector<FastLio2Predict> predicts;
  const Status fed = FastLio2ScanPredicts(Knots(in.window), FastLio2Parameters(),
                                          in.window.t_start(), in.window.t_end(), predicts);
  if (!fed.ok()) return fed;
  FastLio2State x;  // identity, zero position and velocity
  x.bg = in.bg;
  x.ba = in.ba;
  x.grav = FastLio2GravityExact(Vec3::Zero());
  for (const FastLio2Predict& p : predicts) x = FastLio2PredictState(x, p.in, p.dt);
  delta.dR = x.rot.toRotationMatrix();
  delta.dp = x.pos;
  delta.dv = x.vel;
  return Status::Ok();
}

}  // namespace imuconv::kernels
