// The covariance's accumulators of the rk4 kernel (rk4_window.h, part 3 of its derivation):
// M = int Psi D Psi^T over the window, summed per step into NoiseSums and assembled once per
// window (AssembleM); the congruence P_e = Phi_e (P_s + M) Phi_e^T is rk4_window.h's. Psi's free
// bias columns are kept stacked as Y = [Pg; Vg; Pa; Tg] (their layout is declared here, once).
#pragma once

#include "imuconv/kernels/common.h"
#include "imuconv/kernels/left_transition.h"
#include "kernel_config.h"

IMUCONV_KERNEL_BEGIN
namespace rk4_detail {

/// Psi's free bias columns stacked as one 12x3 block, Y = [Pg; Vg; Pa; Tg] (row blocks in
/// that order): their step rules are the same for all four, so each is one pass over 36
/// contiguous numbers, and the walks' products below are columns of Y Y^T (tall axpys that
/// vectorise) instead of eight 3x3 products. [Pg; Vg] first: the one 6-row product then reads
/// the start of a column, where the loop before stored a whole vector (a load that straddles
/// two vector stores waits for both to reach the cache).
constexpr int kYRows = 12, kYSize = 3 * kYRows;
using MatY = Eigen::Matrix<double, kYRows, 3>;
namespace y_row {
constexpr int Pg = 0, Vg = 3, Pa = 6, Tg = 9;
}

/// M's accumulators: M = int Psi D Psi^T assembled from them once per window (AssembleM).
struct NoiseSums {
  // q_g-type terms: sums of weighted outer products of (alpha, U), the weights including the
  // noise densities (see Rk4Step).
  Mat3 aa = Mat3::Zero(), Ua = Mat3::Zero(),
       UU = Mat3::Zero();  ///< alpha alpha^T, U alpha^T, U U^T
  Vec3 a = Vec3::Zero(), U = Vec3::Zero();
  // Walk corrections of the c_v-type (closed-form) terms: sum h^3/12 {1, s_m, s_m^2}.
  double h3 = 0.0, h3_s = 0.0, h3_ss = 0.0;
  // Sums over steps of h Yb Yb^T, only the blocks M needs (rows of Y, then the Y block whose
  // transpose is the column): YTg = [PgTg; VgTg; PaTg; TgTg], YPg = [PgPg; VgPg], VgVg, PaPa.
  MatY YTg = MatY::Zero();
  Eigen::Matrix<double, 6, 3> YPg = Eigen::Matrix<double, 6, 3>::Zero();
  Mat3 VgVg = Mat3::Zero(), PaPa = Mat3::Zero();
  MatY iY = MatY::Zero();  ///< sum over steps of h Yb: int Pg, int Vg, int Pa, int Tg

  /// Adds h Yb Yb^T (the blocks kept above) and h Yb, given hYb = h Yb. Column j of a block
  /// (A, B) is sum_k (h A).col(k) B(j, k): three axpys over the rows of A. Written as plain
  /// loops over the column-major storage so that each instance vectorises them at its own
  /// width (Eigen's packets are fixed at 128 bits by the default target).
  void AddWalks(const MatY& hYb, const MatY& Yb) {
    using namespace y_row;
    const double* hy = hYb.data();  // column k starts at hy + kYRows k
    const double* y = Yb.data();
    for (int j = 0; j < 3; ++j) {
      constexpr int c1 = kYRows, c2 = 2 * kYRows;  // offsets of columns 1 and 2
      const double t0 = y[Tg + j], t1 = y[c1 + Tg + j], t2 = y[c2 + Tg + j];
      double* yt = YTg.data() + kYRows * j;
      for (int i = 0; i < kYRows; ++i) yt[i] += hy[i] * t0 + hy[c1 + i] * t1 + hy[c2 + i] * t2;
      const double g0 = y[Pg + j], g1 = y[c1 + Pg + j], g2 = y[c2 + Pg + j];
      double* yp = YPg.data() + 6 * j;
      for (int i = 0; i < 6; ++i)
        yp[i] += hy[Pg + i] * g0 + hy[c1 + Pg + i] * g1 + hy[c2 + Pg + i] * g2;
      const double v0 = y[Vg + j], v1 = y[c1 + Vg + j], v2 = y[c2 + Vg + j];
      double* vv = VgVg.data() + 3 * j;
      for (int i = 0; i < 3; ++i)
        vv[i] += hy[Vg + i] * v0 + hy[c1 + Vg + i] * v1 + hy[c2 + Vg + i] * v2;
      const double a0 = y[Pa + j], a1 = y[c1 + Pa + j], a2 = y[c2 + Pa + j];
      double* aa_ = PaPa.data() + 3 * j;
      for (int i = 0; i < 3; ++i)
        aa_[i] += hy[Pa + i] * a0 + hy[c1 + Pa + i] * a1 + hy[c2 + Pa + i] * a2;
    }
    double* iy = iY.data();
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < kYRows; ++i) iy[kYRows * k + i] += hy[kYRows * k + i];
  }
};

/// M = int_{t_s}^{t_e} Psi D Psi^T from the sums (lower triangle filled by symmetry).
inline Mat15 AssembleM(const NoiseSums& n, const NoiseVariances& q, double T) {
  using namespace left_idx;
  namespace y = y_row;
  const Mat3 I = Mat3::Identity();
  // The walk blocks by name (see NoiseSums): (A, B) = sum h Ab Bb^T.
  const Mat3 PgPg = n.YPg.topRows<3>(), PgVg = n.YPg.bottomRows<3>().transpose();
  const Mat3 PaTg = n.YTg.middleRows<3>(y::Pa), TgTg = n.YTg.middleRows<3>(y::Tg);
  const Mat3 PgTg = n.YTg.middleRows<3>(y::Pg), TgVg = n.YTg.middleRows<3>(y::Vg).transpose();
  // c_v-type scalars: q_a int {1, s, s^2} in closed form plus the accel walk's corrections.
  const double c1 = q.accel * T + q.accel_walk * n.h3;
  const double cs = q.accel * (0.5 * T * T) + q.accel_walk * n.h3_s;
  const double css = q.accel * (T * T * T / 3.0) + q.accel_walk * n.h3_ss;
  const double c_theta = q.gyro * T + q.gyro_walk * n.h3;  // the sum of the q_g-type weights
  Mat15 M = Mat15::Zero();
  M.block<3, 3>(p, p) =
      (n.aa.trace() + css) * I - n.aa + q.gyro_walk * PgPg + q.accel_walk * n.PaPa;
  M.block<3, 3>(p, theta) = so3::skew(n.a) + q.gyro_walk * PgTg;
  M.block<3, 3>(p, v) = (n.Ua.trace() - cs) * I - n.Ua + q.gyro_walk * PgVg + q.accel_walk * PaTg;
  M.block<3, 3>(p, bg) = q.gyro_walk * n.iY.middleRows<3>(y::Pg);
  M.block<3, 3>(p, ba) = q.accel_walk * n.iY.middleRows<3>(y::Pa);
  M.block<3, 3>(theta, theta) = c_theta * I + q.gyro_walk * TgTg;
  M.block<3, 3>(theta, v) = -so3::skew(n.U) + q.gyro_walk * TgVg;
  M.block<3, 3>(theta, bg) = q.gyro_walk * n.iY.middleRows<3>(y::Tg);
  M.block<3, 3>(v, v) = (n.UU.trace() + c1) * I - n.UU + q.gyro_walk * n.VgVg + q.accel_walk * TgTg;
  M.block<3, 3>(v, bg) = q.gyro_walk * n.iY.middleRows<3>(y::Vg);
  M.block<3, 3>(v, ba) = q.accel_walk * n.iY.middleRows<3>(y::Tg);
  M.block<3, 3>(bg, bg) = (q.gyro_walk * T) * I;
  M.block<3, 3>(ba, ba) = (q.accel_walk * T) * I;
  M.triangularView<Eigen::StrictlyLower>() = M.transpose();
  return M;
}

}  // namespace rk4_detail
IMUCONV_KERNEL_END
