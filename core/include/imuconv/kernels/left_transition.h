// The block structure of a transition matrix in the `left` error state, shared by the
// integrator kernels.
//
// In the left chart (paper, eq. left-dpr..left-dba; order [p, theta, v, bg, ba]) the error
// dynamics of the paper's "IMU Propagation in Detail" are
//   d dp/dt = dv,  d dtheta/dt = -R dbg,  d dv/dt = -[R a]x dtheta - R dba,  d db/dt = 0
// (noise omitted). Nothing feeds back into dtheta except dbg, nothing into dv except dtheta
// and dba, so every transition matrix of this system, continuous or exactly discretised,
// has the form
//
//          p   theta   v    bg     ba
//   p   [  I   P_th   dt I  P_bg   P_ba ]
//   th  [  0    I      0    T_bg    0   ]
//   v   [  0   V_th    I    V_bg   V_ba ]
//   bg  [  0    0      0     I      0   ]
//   ba  [  0    0      0     0      I   ]
//
// with seven free 3x3 blocks and one scalar. The kernels keep Phi in this form: composing
// two costs two 3x3 products instead of a dense 15x15 product, and applying one to a
// covariance touches only the p, theta and v rows and columns.
#pragma once

#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"
#include "imuconv/types.h"

namespace imuconv::kernels {

/// A transition matrix of the left error state in its block form (see the file comment).
struct LeftTransition {
  Mat3 th_bg = Mat3::Zero();
  Mat3 v_th = Mat3::Zero(), v_bg = Mat3::Zero(), v_ba = Mat3::Zero();
  Mat3 p_th = Mat3::Zero(), p_bg = Mat3::Zero(), p_ba = Mat3::Zero();
  double p_v =
      0.0;  ///< the p-v block is p_v * I: position integrates velocity over the elapsed time

  static LeftTransition Identity() { return LeftTransition(); }

  /// this <- step * this, i.e. the transition over a later step applied after this one.
  void PrependStep(const LeftTransition& s) {
    // Block rows of the product (s after a), from the form above:
    //   p:  p_th = a.p_th + s.p_th + s.p_v a.v_th, p_bg = a.p_bg + s.p_th a.th_bg + s.p_v a.v_bg +
    //   s.p_bg,
    //       p_ba = a.p_ba + s.p_v a.v_ba + s.p_ba, p_v = a.p_v + s.p_v
    //   th: th_bg = a.th_bg + s.th_bg
    //   v:  v_th = a.v_th + s.v_th, v_bg = a.v_bg + s.v_th a.th_bg + s.v_bg, v_ba = a.v_ba + s.v_ba
    // p uses the old v and th blocks of `this`, so it is updated first.
    p_bg.noalias() += s.p_th * th_bg;
    p_bg += s.p_v * v_bg + s.p_bg;
    p_th += s.p_th + s.p_v * v_th;
    p_ba += s.p_v * v_ba + s.p_ba;
    p_v += s.p_v;
    v_bg.noalias() += s.v_th * th_bg;
    v_bg += s.v_bg;
    v_th += s.v_th;
    v_ba += s.v_ba;
    th_bg += s.th_bg;
  }

  Mat15 ToMatrix() const {
    using namespace left_idx;
    Mat15 Phi = Mat15::Identity();
    Phi.block<3, 3>(p, theta) = p_th;
    Phi.block<3, 3>(p, v) = p_v * Mat3::Identity();
    Phi.block<3, 3>(p, bg) = p_bg;
    Phi.block<3, 3>(p, ba) = p_ba;
    Phi.block<3, 3>(theta, bg) = th_bg;
    Phi.block<3, 3>(v, theta) = v_th;
    Phi.block<3, 3>(v, bg) = v_bg;
    Phi.block<3, 3>(v, ba) = v_ba;
    return Phi;
  }
};

/// T P T^T for a transition in block form and a symmetric P, once per interval. With
/// T = I + E (E non-zero only in the p, theta and v rows) and C = P E^T (non-zero only in
/// the p, theta and v columns): T P T^T = P + C + C^T + E C, as in the Euler covariance step.
inline Mat15 Congruence(const LeftTransition& T, const Mat15& P) {
  using namespace left_idx;
  // E_p = [0, p_th, p_v I, p_bg, p_ba], E_theta = [0, 0, 0, th_bg, 0], E_v = [0, v_th, 0, v_bg,
  // v_ba].
  Eigen::Matrix<double, 15, 9> C;
  C.middleCols<3>(p).noalias() = P.middleCols<3>(theta) * T.p_th.transpose();
  C.middleCols<3>(p) += T.p_v * P.middleCols<3>(v);
  C.middleCols<3>(p).noalias() += P.middleCols<3>(bg) * T.p_bg.transpose();
  C.middleCols<3>(p).noalias() += P.middleCols<3>(ba) * T.p_ba.transpose();
  C.middleCols<3>(theta).noalias() = P.middleCols<3>(bg) * T.th_bg.transpose();
  C.middleCols<3>(v).noalias() = P.middleCols<3>(theta) * T.v_th.transpose();
  C.middleCols<3>(v).noalias() += P.middleCols<3>(bg) * T.v_bg.transpose();
  C.middleCols<3>(v).noalias() += P.middleCols<3>(ba) * T.v_ba.transpose();
  Mat9 EC;
  EC.middleRows<3>(p).noalias() = T.p_th * C.middleRows<3>(theta);
  EC.middleRows<3>(p) += T.p_v * C.middleRows<3>(v);
  EC.middleRows<3>(p).noalias() += T.p_bg * C.middleRows<3>(bg);
  EC.middleRows<3>(p).noalias() += T.p_ba * C.middleRows<3>(ba);
  EC.middleRows<3>(theta).noalias() = T.th_bg * C.middleRows<3>(bg);
  EC.middleRows<3>(v).noalias() = T.v_th * C.middleRows<3>(theta);
  EC.middleRows<3>(v).noalias() += T.v_bg * C.middleRows<3>(bg);
  EC.middleRows<3>(v).noalias() += T.v_ba * C.middleRows<3>(ba);
  Mat15 out = P;
  out.leftCols<9>() += C;
  out.topRows<9>() += C.transpose();
  out.topLeftCorner<9, 9>() += EC;
  return out;
}

/// Fills the theta columns (v_th, p_th) and p_v of Phi over [t_s, t_s + T] from the nominal
/// start and end states. Since d v_th/dt = -[R a]x while d v/dt = g + R a, and p_th and p
/// integrate v_th and v, the exact flow has
///   v_th = -[v_e - v_s - g T]x,   p_th = -[p_e - p_s - v_s T - g T^2/2]x.
/// The Euler step and RK4 integrate v_th and v with the same weights on the same R a, so the
/// identity holds for them too (up to rounding): these blocks need no per-sample work.
inline void ThetaColumnsFromState(const ImuState& x_s, const ImuState& x_e, double T,
                                  const Vec3& gravity, LeftTransition& Phi) {
  Phi.v_th = -so3::skew(x_e.v - x_s.v - T * gravity);
  Phi.p_th = -so3::skew(x_e.p - x_s.p - T * x_s.v - (0.5 * T * T) * gravity);
  Phi.p_v = T;
}

}  // namespace imuconv::kernels
