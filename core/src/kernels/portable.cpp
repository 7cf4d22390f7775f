// The portable path of the preintegration kernel (portable.h): per step, the Jacobians of
// the step specification (steps.cpp) drive the bias Jacobians and the covariance
// Sigma' = F Sigma F^T + G Q G^T in 3x3 blocks (the recursion of block_recursion.h,
// written with Eigen instead of 4-lane vectors).
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"  // so3_fast.h's 4-lane helpers are never out of line
#endif

#include "portable.h"

#include "imuconv/kernels/common.h"
#include "imuconv/window.h"
#include "so3_fast.h"

namespace imuconv::kernels::detail {
namespace {

/// A Z for a 9x3 column block Z = [Z_t; Z_p; Z_v] (two 3x3 products).
Mat93 ApplyA(const StepJacobians& J, const Mat93& Z) {
  Mat93 Y;
  const Mat3 KZt = J.K * Z.block<3, 3>(0, 0);
  Y.block<3, 3>(0, 0).noalias() = J.A_tt * Z.block<3, 3>(0, 0);
  Y.block<3, 3>(3, 0) = (0.5 * J.dt) * KZt + Z.block<3, 3>(3, 0) + J.dt * Z.block<3, 3>(6, 0);
  Y.block<3, 3>(6, 0) = KZt + Z.block<3, 3>(6, 0);
  return Y;
}

/// A Z for a column block whose theta rows are zero (they stay zero; no products).
Mat93 ApplyAThetaFree(double dt, const Mat93& Z) {
  Mat93 Y;
  Y.block<3, 3>(0, 0).setZero();
  Y.block<3, 3>(3, 0) = Z.block<3, 3>(3, 0) + dt * Z.block<3, 3>(6, 0);
  Y.block<3, 3>(6, 0) = Z.block<3, 3>(6, 0);
  return Y;
}

// ---------------------------------------------------------------------------------------
// Bias Jacobians, shared by both schemes.

/// d x / d(ba, bg) in the additive-p,v chart; rows [theta, p, v]. The theta rows of H_ba
/// stay zero: theta does not see the accelerometer.
struct BiasJacobians {
  Mat93 H_ba = Mat93::Zero();
  Mat93 H_bg = Mat93::Zero();

  /// 9x6, columns [ba, bg] (GTSAM's layout).
  Mat96 Assemble() const {
    Mat96 J;
    J.leftCols<3>() = H_ba;
    J.rightCols<3>() = H_bg;
    return J;
  }
};

/// H_ba' = A H_ba - B, H_bg' = A H_bg - C, with the Jacobians of the state before the step.
void PropagateBiasJacobians(const StepJacobians& J, BiasJacobians& H) {
  const double dt = J.dt, h = 0.5 * dt * dt;
  H.H_ba = ApplyAThetaFree(dt, H.H_ba);
  H.H_ba.block<3, 3>(3, 0) -= h * J.N;
  H.H_ba.block<3, 3>(6, 0) -= dt * J.N;
  H.H_bg = ApplyA(J, H.H_bg);
  H.H_bg.block<3, 3>(0, 0) -= J.C_t;
}

/// Sigma = [P X; X^T S] with P = cov(delta x9), X = cov(delta x9, delta b) (columns
/// [ba, bg]) and S = diag(s_ba I3, s_bg I3): with isotropic random walks and zero initial
/// bias uncertainty the bias block is exactly the accumulated random walk, and the
/// theta rows of the ba columns of X stay zero.
struct CombinedCovariance {
  Mat9 P = Mat9::Zero();
  Mat96 X = Mat96::Zero();
  double s_ba = 0.0, s_bg = 0.0;

  Mat15 Assemble() const {
    Mat15 S = Mat15::Zero();
    S.topLeftCorner<9, 9>() = P;
    S.block<9, 6>(0, 9) = X;
    S.block<6, 9>(9, 0) = X.transpose();
    S.block<3, 3>(9, 9).diagonal().setConstant(s_ba);
    S.block<3, 3>(12, 12).diagonal().setConstant(s_bg);
    return S;
  }
};

/// Sigma' = F Sigma F^T + G Q G^T for one step (see the header comment), in 3x3 blocks.
///
/// Rather than multiplying 9x9 and 15x15 matrices, the step is written through the few
/// 3-vectors it is linear in:
///   theta~ = A_tt theta,  u = K theta,  g = C_t (db_g + n_g),  w = N (db_a + n_a),
///   q = p + dt v,  r = u + dt w,
///   theta' = theta~ + g,  p' = q + (dt/2) r,  v' = v + r,
/// so every 3x3 product is one of these maps applied to a block of Sigma (17 products a
/// step), the rest are scaled sums, and the diagonal blocks come out symmetric. With the
/// noise and the bias block isotropic, cov(w, w) = (s_ba + s_a^2/dt) I, and g is
/// correlated with the state only through the bias columns of X; w is uncorrelated with
/// theta (cov(dtheta, dba) = 0).
/// PreintegratedImuMeasurements' 9x9 covariance is P of this recursion run with zero
/// random walk (X and the bias block then stay zero).
void PropagateCombined(const StepJacobians& J, const NoiseVariances& q, CombinedCovariance& c) {
  const double dt = J.dt, half_dt = 0.5 * dt, h = 0.5 * dt * dt;
  const double kw = c.s_ba + q.accel / dt;  // cov(w, w) = kw I (N is a rotation)
  const double kg = c.s_bg + q.gyro / dt;   // cov(g, g) = kg C_t C_t^T

  const auto blk = [](auto& M, int i, int j) { return M.template block<3, 3>(3 * i, 3 * j); };
  const Mat3 Ptt = blk(c.P, 0, 0), Ptp = blk(c.P, 0, 1), Ptv = blk(c.P, 0, 2);
  const Mat3 Ppp = blk(c.P, 1, 1), Ppv = blk(c.P, 1, 2), Pvv = blk(c.P, 2, 2);
  const Mat3 Xp_a = c.X.block<3, 3>(3, 0), Xv_a = c.X.block<3, 3>(6, 0);
  const Mat3 Xt_g = c.X.block<3, 3>(0, 3), Xp_g = c.X.block<3, 3>(3, 3),
             Xv_g = c.X.block<3, 3>(6, 3);
  const Mat3 Ptq = Ptp + dt * Ptv;     // cov(theta, q)
  const Mat3 Xq_a = Xp_a + dt * Xv_a;  // cov(q, db_a)
  const Mat3 Xq_g = Xp_g + dt * Xv_g;  // cov(q, db_g)

  // theta~ and u against theta, q, v.
  const Mat3 AP = J.A_tt * Ptt, KP = J.K * Ptt;
  Mat3 TT = AP * J.A_tt.transpose();     // cov(theta~, theta~)
  const Mat3 TU = AP * J.K.transpose();  // cov(theta~, u)
  Mat3 UU = KP * J.K.transpose();        // cov(u, u)
  const Mat3 Tq = J.A_tt * Ptq, Tv = J.A_tt * Ptv;
  const Mat3 Uq = J.K * Ptq, Uv = J.K * Ptv;
  // Bias columns through the step: A applied to X's bg column.
  const Mat3 AXg = J.A_tt * Xt_g, KXg = J.K * Xt_g;
  // cov(., g) for theta~, v' and p' (without their own g or w parts).
  const Mat3 Ct_T = J.C_t.transpose();
  const Mat3 Gt = AXg * Ct_T;
  const Mat3 Gv = (Xv_g + KXg) * Ct_T;
  const Mat3 Gp = (Xq_g + half_dt * KXg) * Ct_T;
  Mat3 CC = J.C_t * Ct_T;
  // cov(., w) for q and v.
  const Mat3 Nt = J.N.transpose();
  const Mat3 Wq = Xq_a * Nt, Wv = Xv_a * Nt;

  // r = u + dt w.
  const Mat3 Rq = Uq + dt * Wq.transpose();  // cov(r, q)
  const Mat3 Rv = Uv + dt * Wv.transpose();  // cov(r, v)
  UU.diagonal().array() += dt * dt * kw;     // now cov(r, r)
  const Mat3& RR = UU;
  // Symmetrise the three products that are symmetric in exact arithmetic.
  TT = 0.5 * (TT + TT.transpose()).eval();
  CC = 0.5 * (CC + CC.transpose()).eval();
  const Mat3 RRs = 0.5 * (RR + RR.transpose());

  const Mat3 Pqq = Ppp + dt * (Ppv + Ppv.transpose()) + (dt * dt) * Pvv;
  const Mat3 Pqv = Ppv + dt * Pvv;

  // Symmetric parts are summed first so the diagonal blocks stay exactly symmetric.
  const Mat3 Ntt = TT + (Gt + Gt.transpose()) + kg * CC;
  const Mat3 Ntp = Tq + half_dt * TU + Gp.transpose();
  const Mat3 Ntv = Tv + TU + Gv.transpose();
  const Mat3 Npp = Pqq + half_dt * (Rq + Rq.transpose()) + (half_dt * half_dt) * RRs;
  const Mat3 Npv = Pqv + Rq.transpose() + half_dt * Rv + half_dt * RRs;
  const Mat3 Nvv = Pvv + (Rv + Rv.transpose()) + RRs;

  blk(c.P, 0, 0) = Ntt;
  blk(c.P, 0, 1) = Ntp;
  blk(c.P, 0, 2) = Ntv;
  blk(c.P, 1, 0) = Ntp.transpose();
  blk(c.P, 1, 1) = Npp;
  blk(c.P, 1, 2) = Npv;
  blk(c.P, 2, 0) = Ntv.transpose();
  blk(c.P, 2, 1) = Npv.transpose();
  blk(c.P, 2, 2) = Nvv;

  // X' = A X + Fb S.
  c.X.block<3, 3>(3, 0) = Xq_a + (h * c.s_ba) * J.N;
  c.X.block<3, 3>(6, 0) = Xv_a + (dt * c.s_ba) * J.N;
  c.X.block<3, 3>(0, 3) = AXg + c.s_bg * J.C_t;
  c.X.block<3, 3>(3, 3) = Xq_g + half_dt * KXg;
  c.X.block<3, 3>(6, 3) = Xv_g + KXg;

  c.s_ba += dt * q.accel_walk;
  c.s_bg += dt * q.gyro_walk;
}

/// One manifold step with its Jacobians in the chart (dR Exp(dtheta), dp + ddp, dv + ddv):
///   A_tt = E^T,  K = -dR [acc]x dt,  N = dR,  C_t = Jr(omega dt) dt.
void ManifoldStepRightChart(const Vec3& acc, const Vec3& omega, double dt, ManifoldIncrement& s,
                            StepJacobians& J) {
  const double h = 0.5 * dt * dt;
  const Vec3 phi = omega * dt;
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const ExpJrCoefs k = ComputeExpJrCoefs(t, t2);
  const Mat3 S = so3::skew(phi), S2 = S * S;
  const Mat3 E = Mat3::Identity() + k.a * S + k.b * S2;
  const Mat3 Jr = Mat3::Identity() - k.b * S + k.c * S2;
  J.dt = dt;
  J.A_tt = E.transpose();
  J.K.noalias() = (-dt) * s.dR * so3::skew(acc);
  J.N = s.dR;
  J.C_t = dt * Jr;
  const Vec3 a_start = s.dR * acc;
  s.dp += dt * s.dv + h * a_start;
  s.dv += dt * a_start;
  s.dR = s.dR * E;
  s.dt += dt;
}

/// The manifold covariance in the NavState chart (dR Exp(dth), dp + dR ddp, dv + dR ddv):
/// Sigma_nav = T Sigma T^T with T = blockdiag(I, dR^T, dR^T, I6) at the final estimate.
Mat15 ManifoldCovarianceInNavStateChart(const Mat3& dR, const CombinedCovariance& c) {
  Mat15 S = c.Assemble();
  const Mat3 Rt = dR.transpose();
  for (int blk = 3; blk <= 6; blk += 3) {
    S.block<3, 15>(blk, 0) = Rt * S.block<3, 15>(blk, 0);
    S.block<15, 3>(0, blk) = S.block<15, 3>(0, blk) * dR;
  }
  return 0.5 * (S + S.transpose());  // rows and columns were rotated in separate roundings
}

/// Runs `step` over the window's held values (see Hold) and the recursion from its
/// Jacobians.
template <bool kCovariance, Hold kHold, typename StepFn>
void Run(const PreintegrationInput& in, StepFn step, BiasJacobians& H, CombinedCovariance& cov) {
  const SampleWindow& w = in.window;
  const NoiseVariances q = NoiseVariances(in.noise);
  StepJacobians J;
  for (std::size_t j = 0; j + 1 < w.size(); ++j) {
    const ImuSample& s = w[j];
    if constexpr (kHold == Hold::Euler) {
      step(Vec3(s.accel - in.ba), Vec3(s.gyro - in.bg), w[j + 1].t - s.t, J);
    } else {
      const ImuSample& n = w[j + 1];
      step(Vec3(0.5 * (s.accel + n.accel) - in.ba), Vec3(0.5 * (s.gyro + n.gyro) - in.bg),
           n.t - s.t, J);
    }
    PropagateBiasJacobians(J, H);
    if constexpr (kCovariance) PropagateCombined(J, q, cov);
  }
}

template <bool kCovariance, Hold kHold, typename StepFn>
void RunAndAssemble(const PreintegrationInput& in, StepFn step, Mat96& J_inc_bias,
                    CombinedCovariance& cov) {
  BiasJacobians H;
  Run<kCovariance, kHold>(in, step, H, cov);
  J_inc_bias = H.Assemble();
}

/// RunAndAssemble with the covariance or without, as asked at run time: `cov` is left
/// untouched without it.
template <Hold kHold = Hold::Euler, typename StepFn>
void RunAndAssemble(const PreintegrationInput& in, bool covariance, StepFn step, Mat96& J_inc_bias,
                    CombinedCovariance& cov) {
  if (covariance)
    RunAndAssemble<true, kHold>(in, step, J_inc_bias, cov);
  else
    RunAndAssemble<false, kHold>(in, step, J_inc_bias, cov);
}

}  // namespace

void ManifoldPortable(const PreintegrationInput& in, bool covariance, ManifoldIncrement& inc,
                      Mat96& J_inc_bias, Mat15& cov) {
  const auto step = [&inc](const Vec3& a, const Vec3& w, double dt, StepJacobians& J) {
    ManifoldStepRightChart(a, w, dt, inc, J);
  };
  CombinedCovariance c;
  RunAndAssemble(in, covariance, step, J_inc_bias, c);
  if (covariance) cov = ManifoldCovarianceInNavStateChart(inc.dR, c);
}

void TangentPortable(const PreintegrationInput& in, bool covariance, TangentIncrement& inc,
                     Mat96& J_inc_bias, Mat15& cov) {
  const auto step = [&inc](const Vec3& a, const Vec3& w, double dt, StepJacobians& J) {
    TangentStep(a, w, dt, inc, J);
  };
  CombinedCovariance c;
  RunAndAssemble(in, covariance, step, J_inc_bias, c);
  if (covariance) cov = c.Assemble();
}

void ManifoldStartFramePortable(const PreintegrationInput& in, Hold hold, bool covariance,
                                StartFrameManifold& out) {
  ManifoldIncrement& inc = out.increment;
  const auto step = [&inc](const Vec3& a, const Vec3& w, double dt, StepJacobians& J) {
    ManifoldStep(a, w, dt, inc, J);
  };
  CombinedCovariance c;
  if (hold == Hold::Euler)
    RunAndAssemble<Hold::Euler>(in, covariance, step, out.J_inc_bias, c);
  else
    RunAndAssemble<Hold::Midpoint>(in, covariance, step, out.J_inc_bias, c);
  if (covariance) out.cov = c.Assemble();
}

}  // namespace imuconv::kernels::detail
