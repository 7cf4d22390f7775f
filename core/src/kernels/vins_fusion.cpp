// VINS-Fusion's midpoint preintegration (see imuconv/kernels/vins_fusion.h for the scheme,
// its error state and its noise). Upstream forms the dense F (15x15) and V (15x18) and
// multiplies them out; here the same numbers are formed from their nonzero 3x3 blocks:
//
//   F = [ I  F_pt  I dt  F_pa  F_pg ]      V = [ V_pa0  V_pg  V_pa1  V_pg  0     0    ]
//       [ 0  F_tt  0     0    -I dt ]          [ 0      I dt/2 0     I dt/2 0     0    ]
//       [ 0  F_vt  I     F_va  F_vg ]          [ V_va0  V_vg  V_va1  V_vg  0     0    ]
//       [ 0  0     0     I     0    ]          [ 0      0     0      0     I dt  0    ]
//       [ 0  0     0     0     I    ]          [ 0      0     0      0     0     I dt ]
//
// with columns of V for [n_a0, n_g0, n_a1, n_g1, n_ba, n_bg].
#include "imuconv/kernels/vins_fusion.h"

#include <cmath>

#include "imuconv/kernels/preintegration.h"
#include "imuconv/so3.h"

namespace imuconv::kernels {

namespace {

constexpr int kP = 0, kTheta = 3, kV = 6, kBa = 9, kBg = 12;

/// The nonzero off-identity blocks of one step's F.
struct StepMatrix {
  double dt = 0.0;
  Mat3 F_pt, F_pa, F_pg, F_tt, F_vt, F_va, F_vg;
};

/// out = F M for any 15-column M (rows of F times M, block by block).
void ApplyStep(const StepMatrix& F, const Mat15& M, Mat15& out) {
  const auto p = M.middleRows<3>(kP), t = M.middleRows<3>(kTheta), v = M.middleRows<3>(kV),
             ba = M.middleRows<3>(kBa), bg = M.middleRows<3>(kBg);
  out.middleRows<3>(kP) = p + F.F_pt * t + F.dt * v + F.F_pa * ba + F.F_pg * bg;
  out.middleRows<3>(kTheta) = F.F_tt * t - F.dt * bg;
  out.middleRows<3>(kV) = F.F_vt * t + v + F.F_va * ba + F.F_vg * bg;
  out.middleRows<3>(kBa) = ba;
  out.middleRows<3>(kBg) = bg;
}

/// The four per-step variances of upstream's noise matrix at step length dt.
struct StepVariances {
  double acc_n2, gyr_n2, acc_w2, gyr_w2;
};

/// The four numbers squared, once per interval.
StepVariances Squares(const ImuNoise& n) {
  return {n.accel_noise_density * n.accel_noise_density,
          n.gyro_noise_density * n.gyro_noise_density, n.accel_random_walk * n.accel_random_walk,
          n.gyro_random_walk * n.gyro_random_walk};
}

StepVariances VariancesAt(const StepVariances& squares, VinsNoiseMapping mapping, double dt) {
  if (mapping == VinsNoiseMapping::kAsConfigured) return squares;
  // acc_n^2 = 2 sigma_a^2 / dt, acc_w^2 = sigma_wa^2 / dt (header): the per-step variances
  // of continuous white noise through V's dt factors.
  return {2.0 * squares.acc_n2 / dt, 2.0 * squares.gyr_n2 / dt, squares.acc_w2 / dt,
          squares.gyr_w2 / dt};
}

/// Adds V diag(noise) V^T to the covariance, block by block (V as in the file comment);
/// R1_a1_x = R1 [a_1]x.
void AddStepNoise(const Mat3& R0, const Mat3& R1, const Mat3& R1_a1_x, double dt,
                  const StepVariances& s, Mat15& cov) {
  const double dt2 = dt * dt;
  const Mat3 V_pa0 = (0.25 * dt2) * R0, V_pa1 = (0.25 * dt2) * R1, V_va0 = (0.5 * dt) * R0,
             V_va1 = (0.5 * dt) * R1;
  const Mat3 V_pg = (-0.125 * dt2 * dt) * R1_a1_x, V_vg = (-0.25 * dt2) * R1_a1_x;
  // The two gyro noises enter every row through the same block, so they add as 2 gyr_n^2.
  const double g2 = 2.0 * s.gyr_n2;
  const Mat3 Q_pp = s.acc_n2 * (V_pa0 * V_pa0.transpose() + V_pa1 * V_pa1.transpose()) +
                    g2 * (V_pg * V_pg.transpose());
  const Mat3 Q_pv = s.acc_n2 * (V_pa0 * V_va0.transpose() + V_pa1 * V_va1.transpose()) +
                    g2 * (V_pg * V_vg.transpose());
  const Mat3 Q_vv = s.acc_n2 * (V_va0 * V_va0.transpose() + V_va1 * V_va1.transpose()) +
                    g2 * (V_vg * V_vg.transpose());
  const Mat3 Q_pt = (g2 * 0.5 * dt) * V_pg, Q_vt = (g2 * 0.5 * dt) * V_vg;  // against V_t = I dt/2
  const double q_tt = g2 * 0.25 * dt2;
  cov.block<3, 3>(kP, kP) += Q_pp;
  cov.block<3, 3>(kP, kV) += Q_pv;
  cov.block<3, 3>(kV, kP) += Q_pv.transpose();
  cov.block<3, 3>(kV, kV) += Q_vv;
  cov.block<3, 3>(kP, kTheta) += Q_pt;
  cov.block<3, 3>(kTheta, kP) += Q_pt.transpose();
  cov.block<3, 3>(kV, kTheta) += Q_vt;
  cov.block<3, 3>(kTheta, kV) += Q_vt.transpose();
  cov.block<3, 3>(kTheta, kTheta).diagonal().array() += q_tt;
  cov.block<3, 3>(kBa, kBa).diagonal().array() += s.acc_w2 * dt2;
  cov.block<3, 3>(kBg, kBg).diagonal().array() += s.gyr_w2 * dt2;
}

}  // namespace

Status IntegrateVinsFusion(const PreintegrationInput& in, VinsNoiseMapping mapping,
                           VinsFusionPreintegration& out, bool jacobians) {
  if (Status s = CheckPreintegrationInput(in); !s.ok()) return s;
  const SampleWindow& w = in.window;
  out = VinsFusionPreintegration{};
  const StepVariances squares = Squares(in.noise);
  Mat15 FM, FMt;
  StepMatrix F;
  const Mat3 I = Mat3::Identity();
  for (std::size_t k = 0; k + 1 < w.size(); ++k) {
    const ImuSample& s0 = w[k];
    const ImuSample& s1 = w[k + 1];
    const double dt = s1.t - s0.t;
    const Eigen::Quaterniond& q = out.delta_q;
    const Vec3 omega = 0.5 * (s0.gyro + s1.gyro) - in.bg;
    const Vec3 a0 = s0.accel - in.ba, a1 = s1.accel - in.ba;
    const Eigen::Quaterniond q1 =
        q * Eigen::Quaterniond(1.0, omega.x() * dt / 2, omega.y() * dt / 2, omega.z() * dt / 2);
    const Vec3 acc = 0.5 * (q * a0 + q1 * a1);
    if (jacobians) {
      const Mat3 R0 = q.toRotationMatrix(), R1 = q1.toRotationMatrix();
      const Mat3 E =
          I - dt * so3::skew(omega);  // first-order Exp(-omega dt): upstream's rotation block
      // The products F and V share, formed once: R1 [a_1]x, the rotation column's
      // R0 [a_0]x + R1 [a_1]x E and the accelerometer column's R0 + R1.
      const Mat3 R1_a1_x = R1 * so3::skew(a1);
      const Mat3 K = R0 * so3::skew(a0) + R1_a1_x * E, R_sum = R0 + R1;

      F.dt = dt;
      F.F_tt = E;
      F.F_pt = (-0.25 * dt * dt) * K;
      F.F_vt = (-0.5 * dt) * K;
      F.F_pa = (-0.25 * dt * dt) * R_sum;
      F.F_va = (-0.5 * dt) * R_sum;
      F.F_pg = (0.25 * dt * dt * dt) * R1_a1_x;
      F.F_vg = (0.5 * dt * dt) * R1_a1_x;

      ApplyStep(F, out.jacobian, FM);
      out.jacobian = FM;
      // cov' = F cov F^T = (F (F cov)^T)^T, cov symmetric.
      ApplyStep(F, out.covariance, FM);
      ApplyStep(F, FM.transpose(), FMt);
      out.covariance = FMt.transpose();
      AddStepNoise(R0, R1, R1_a1_x, dt, VariancesAt(squares, mapping, dt), out.covariance);
    }

    out.delta_p += out.delta_v * dt + (0.5 * dt * dt) * acc;
    out.delta_v += dt * acc;
    out.delta_q = q1.normalized();
    out.sum_dt += dt;
  }
  return Status::Ok();
}

namespace {
/// The increment as both paths write it.
PreintIncrement IncrementOf(const VinsFusionPreintegration& r) {
  PreintIncrement delta;
  delta.dR = r.delta_q.toRotationMatrix();
  delta.dp = r.delta_p;
  delta.dv = r.delta_v;
  return delta;
}
}  // namespace

Status IntegrateVinsFusion(const PreintegrationInput& in, VinsNoiseMapping mapping,
                           Preintegrated& out) {
  VinsFusionPreintegration r;
  if (Status s = IntegrateVinsFusion(in, mapping, r); !s.ok()) return s;
  out.dt = r.sum_dt;
  out.delta = IncrementOf(r);
  out.bg_hat = in.bg;
  out.ba_hat = in.ba;
  out.cov = r.covariance;
  out.J_bias = r.jacobian.block<9, 6>(0, kBa);
  return Status::Ok();
}

Status VinsFusionIncrementMean(const PreintegrationInput& in, PreintIncrement& delta) {
  VinsFusionPreintegration r;
  // The mapping is read only by the covariance's branch, which does not run here.
  if (Status s = IntegrateVinsFusion(in, VinsNoiseMapping::kFromDensities, r, false); !s.ok())
    return s;
  delta = IncrementOf(r);
  return Status::Ok();
}

}  // namespace imuconv::kernels
