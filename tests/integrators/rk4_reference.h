// The RK4 kernel as it was before the variation-of-constants covariance (git 0599b98,
// core/include/imuconv/kernels/rk4.h), kept as an independent cross-check of the kernel: the
// Lie-group RK4 (Munthe-Kaas) of the state, with Phi's bias columns and the covariance
// dP/dt = F P + P F^T + G Qc G^T as one RK4 system on the same four stages. It is fourth
// order in all three but costs ~3600 flops per sample on the covariance; the kernel and this
// reference must agree to their O(dt^4) discretisation error (rk4_cross_check.cpp).
#pragma once

#include "imuconv/kernels/common.h"
#include "imuconv/kernels/left_transition.h"

namespace imuconv::test::rk4_reference {

using namespace imuconv::kernels;

namespace rk4_detail {

/// The noise diagonal G Qc G^T (state independent, see the file comment).
inline Vec15 ProcessNoiseDiagonal(const NoiseVariances& q) {
  using namespace left_idx;
  Vec15 d = Vec15::Zero();
  d.segment<3>(theta).setConstant(q.gyro);
  d.segment<3>(v).setConstant(q.accel);
  d.segment<3>(bg).setConstant(q.gyro_walk);
  d.segment<3>(ba).setConstant(q.accel_walk);
  return d;
}

/// The p, theta and v columns of P F^T, which is all of it: F is non-zero only in its p, theta
/// and v rows, F_p = [0, 0, I, 0, 0], F_theta = [0, 0, 0, -R, 0], F_v = [0, -[R a]x, 0, 0, -R].
/// Built from whole columns of P, contiguous in Eigen's column-major storage.
inline void CovarianceRateColumns(const Mat3& R, const Mat3& Ra_skew, const Mat15& P,
                                  Eigen::Matrix<double, 15, 9>& PFt) {
  using namespace left_idx;
  PFt.middleCols<3>(p) = P.middleCols<3>(v);
  const Mat3 minus_Rt = -R.transpose();
  AssignTimes3x3(P.middleCols<3>(bg), minus_Rt, PFt.middleCols<3>(theta));
  AssignTimes3x3(P.middleCols<3>(theta), Ra_skew, PFt.middleCols<3>(v));  // -[R a]x^T = [R a]x
  AddTimes3x3(P.middleCols<3>(ba), minus_Rt, PFt.middleCols<3>(v));
}

/// P += c (G + G^T + D) for G = [PFt, 0] (15x15): the symmetric rate F P + P F^T + D added
/// without forming it.
inline void AddSymmetricRate(const Eigen::Matrix<double, 15, 9>& PFt, const Vec15& noise_diag, double c, Mat15& P) {
  P.leftCols<9>() += c * PFt;
  P.topLeftCorner<9, 9>() += c * PFt.topRows<9>().transpose();
  P.topRightCorner<9, 6>() += c * PFt.bottomRows<6>().transpose();
  P.diagonal() += c * noise_diag;
}

}  // namespace rk4_detail

/// Input of one RK4 step at its start, middle and end, biases already removed.
struct Rk4StepInput {
  Vec3 w0, wm, w1;  ///< body rate
  Vec3 a0, am, a1;  ///< specific force
};

/// One classical RK4 step of length h of the state and, as kOut asks, of the free blocks
/// of Phi and of the covariance P (the Basalt-style static step; biases are constant).
template <Outputs kOut>
inline void Rk4Step(ImuState& x, LeftTransition& Phi, Mat15& P, const Rk4StepInput& u, double h,
                    const Vec3& gravity, const Vec15& noise_diag) {
  using namespace rk4_detail;
  constexpr bool kPhi = WantsTransition(kOut), kCov = WantsCovariance(kOut);
  const double half_h = 0.5 * h;

  // Stage c = 0, 1/2, 1/2, 1. The rotation coordinate of stage i is phi_i = c_i h k_{i-1}^phi.
  Mat3 R[4];
  Vec3 Ra[4];
  Vec3 k_phi[4], k_v[4], v_stage[4];
  R[0] = x.R;
  k_phi[0] = u.w0;  // Jr^{-1}(0) = I
  v_stage[0] = x.v;
  Ra[0] = R[0] * u.a0;
  k_v[0] = gravity + Ra[0];
  for (int i = 1; i < 4; ++i) {
    const double c_h = i < 3 ? half_h : h;
    const Vec3 phi = c_h * k_phi[i - 1];
    Mat3 dR;
    ExpAndJr(phi, dR, nullptr);
    R[i].noalias() = x.R * dR;
    const Vec3& w = i < 3 ? u.wm : u.w1;
    const Vec3& a = i < 3 ? u.am : u.a1;
    k_phi[i] = JrInvTimes(phi, w);
    v_stage[i] = x.v + c_h * k_v[i - 1];
    Ra[i] = R[i] * a;
    k_v[i] = gravity + Ra[i];
  }
  const double h6 = h / 6.0;

  if constexpr (kPhi) {
    // Phi's bias columns as one more RK4 system driven by the same stage states (the theta
    // columns follow from the state, see ThetaColumnsFromState). Their rates, from
    // d Phi/dt = F Phi:  th_bg' = v_ba' = -R, v_bg' = -[R a]x th_bg, p_bg' = v_bg, p_ba' = v_ba.
    // th_bg and v_ba have the same rate and start, so v_ba = th_bg throughout.
    Mat3 th_bg = Phi.th_bg, v_bg = Phi.v_bg;  // stage values
    Mat3 rate_v_bg;
    Mat3 sum_R = Mat3::Zero(), sum_rate_v_bg = Mat3::Zero(), sum_th_bg = Mat3::Zero(), sum_v_bg = Mat3::Zero();
    for (int i = 0; i < 4; ++i) {
      const double weight = (i == 0 || i == 3) ? 1.0 : 2.0;
      if (i > 0) {
        const double c_h = i < 3 ? half_h : h;
        th_bg = Phi.th_bg - c_h * R[i - 1];
        v_bg = Phi.v_bg + c_h * rate_v_bg;
      }
      rate_v_bg.noalias() = -so3::skew(Ra[i]) * th_bg;
      sum_R += weight * R[i];
      sum_rate_v_bg += weight * rate_v_bg;
      sum_th_bg += weight * th_bg;
      sum_v_bg += weight * v_bg;
    }
    Phi.p_bg += h6 * sum_v_bg;
    Phi.p_ba += h6 * sum_th_bg;
    Phi.th_bg -= h6 * sum_R;
    Phi.v_bg += h6 * sum_rate_v_bg;
    Phi.v_ba = Phi.th_bg;
  }

  if constexpr (kCov) {
    // RK4 on dP/dt = F P + P F^T + D, keeping only P F^T (15x9) per stage:
    // P_i = P + c_i h (G_{i-1} + G_{i-1}^T + D), and P += h/6 (S + S^T) + h D with S the
    // weighted sum of the G_i.
    Eigen::Matrix<double, 15, 9> PFt, sum_PFt;
    Mat15 P_stage;
    CovarianceRateColumns(R[0], so3::skew(Ra[0]), P, PFt);
    sum_PFt = PFt;
    for (int i = 1; i < 4; ++i) {
      const double c_h = i < 3 ? half_h : h;
      P_stage = P;
      AddSymmetricRate(PFt, noise_diag, c_h, P_stage);
      CovarianceRateColumns(R[i], so3::skew(Ra[i]), P_stage, PFt);
      sum_PFt += (i < 3 ? 2.0 : 1.0) * PFt;
    }
    AddSymmetricRate(sum_PFt, 6.0 * noise_diag, h6, P);  // the weights sum to 6
  }

  // The state last: the stages above read x.R and x.v at the start of the step.
  const Vec3 phi = h6 * (k_phi[0] + 2.0 * (k_phi[1] + k_phi[2]) + k_phi[3]);
  Mat3 dR;
  ExpAndJr(phi, dR, nullptr);
  x.p += h6 * (v_stage[0] + 2.0 * (v_stage[1] + v_stage[2]) + v_stage[3]);
  x.v += h6 * (k_v[0] + 2.0 * (k_v[1] + k_v[2]) + k_v[3]);
  x.R = x.R * dR;
}

/// Integrates over the whole window with `substeps` RK4 steps per knot interval, without
/// checking the input (see PropagateRk4). Fills out.x_e, and out.Phi and out.cov as asked.
template <Outputs kOut = Outputs::All>
inline void IntegrateRk4(const PropagationInput& in, PropagationResult& out, int substeps = 1) {
  constexpr bool kPhi = WantsTransition(kOut), kCov = WantsCovariance(kOut);
  const SampleWindow& w = in.window;
  const Vec15 noise_diag = rk4_detail::ProcessNoiseDiagonal(NoiseVariances(in.noise));
  ImuState x = in.x_s;
  LeftTransition Phi;
  Mat15 P;
  if constexpr (kCov) P = in.cov_s;
  const std::size_t intervals = w.size() - 1;
  const double inv_n = 1.0 / substeps;
  const ImuSample* k0 = &w[0];
  Rk4StepInput u;
  for (std::size_t k = 0; k < intervals; ++k) {
    const ImuSample* k1 = &w[k + 1];
    const double dt = k1->t - k0->t;
    const Vec3 w_k0 = k0->gyro - x.bg, a_k0 = k0->accel - x.ba;
    const Vec3 w_k1 = k1->gyro - x.bg, a_k1 = k1->accel - x.ba;
    if (substeps == 1) {
      u.w0 = w_k0, u.w1 = w_k1, u.a0 = a_k0, u.a1 = a_k1;
      u.wm = 0.5 * (w_k0 + w_k1), u.am = 0.5 * (a_k0 + a_k1);
      Rk4Step<kOut>(x, Phi, P, u, dt, in.gravity, noise_diag);
    } else {
      const Vec3 dw = w_k1 - w_k0, da = a_k1 - a_k0;
      const double h = dt * inv_n;
      u.w1 = w_k0, u.a1 = a_k0;
      for (int i = 0; i < substeps; ++i) {
        // Linear interpolation at the substep's start, middle and end (fractions of dt).
        const double s_mid = (i + 0.5) * inv_n, s_end = (i + 1) * inv_n;
        u.w0 = u.w1, u.a0 = u.a1;
        u.wm = w_k0 + s_mid * dw, u.am = a_k0 + s_mid * da;
        u.w1 = i + 1 == substeps ? w_k1 : Vec3(w_k0 + s_end * dw);
        u.a1 = i + 1 == substeps ? a_k1 : Vec3(a_k0 + s_end * da);
        Rk4Step<kOut>(x, Phi, P, u, h, in.gravity, noise_diag);
      }
    }
    k0 = k1;
  }
  out.x_e = x;
  if constexpr (kPhi) {
    ThetaColumnsFromState(in.x_s, x, w.t_end() - w.t_start(), in.gravity, Phi);
    out.Phi = Phi.ToMatrix();
  }
  if constexpr (kCov) out.cov = 0.5 * (P + P.transpose());
}

}  // namespace imuconv::test::rk4_reference
