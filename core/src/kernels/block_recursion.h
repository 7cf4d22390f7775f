// The block recursion of the preintegration kernel (kernels/preintegration.h): one step of
// the covariance and the bias Jacobians of GTSAM's two schemes in 3x3 SIMD blocks.
//
//   manifold: the increment (dR, dp, dv) is a NavState updated on the manifold
//             (GTSAM's ManifoldPreintegration);
//   tangent:  the increment is the 9-vector xi = [theta, p, v] with dR = Exp(theta),
//             integrated in the tangent space at the identity (GTSAM's
//             TangentPreintegration).
//
// Both are driven with a zero-order hold: knot j of the window is held over
// [t_j, t_j+1] (the discrete form of the paper's eq. preint-theta..preint-v). Each step
// has Jacobians in GTSAM's notation,
//   A = d x' / d x (9x9),  B = d x' / d acc (9x3),  C = d x' / d omega (9x3),
// which drive both the bias Jacobians (inputs move by minus the bias change)
//   H_ba' = A H_ba - B,   H_bg' = A H_bg - C,
// and the covariance of the 15-state [theta, p, v, ba, bg] (GTSAM's preintMeasCov order):
//   F = [A  Fb; 0  I6],  Fb = [0 C_theta; B_p 0; B_v 0],
//   Sigma' = F Sigma F^T + diag(B (s_a^2/dt) B^T + C (s_g^2/dt) C^T,  dt q_a^2 I, dt q_g^2 I),
// (s_a, s_g: white-noise densities; q_a, q_g: random-walk densities; GTSAM's
// integrationCovariance and biasAccOmegaInit are zero), i.e. the first-order discrete
// propagation of the paper's section 2.1 with the bias random walk Delta b (eq. preint-b)
// appended. The bias error state of that covariance is delta b = -Delta b (paper, "GTSAM
// Peculiarities", eq. preint-error-db), which is why Fb enters with the sign of
// d x'/d(acc, omega) rather than of d x'/d(bias).
//
// Charts of the recursion. p and v errors are additive in the start frame for both
// schemes. Every step then has the pattern
//   A = [A_tt 0 0; K dt/2  I  I dt; K  0  I],  B = [0; N dt^2/2; N dt],  C = [C_t; 0; 0]
// with N a rotation (StepJacobians below).
//   manifold: the rotation error is taken in the START frame, Exp(phi) dR. Then
//             A_tt = I exactly and K = -dt [dR acc]x is a cross product, so the step has
//             no general 3x3 product in its transition at all (six of the tangent
//             scheme's eighteen remain, all against the noise maps C and N). GTSAM's
//             NavState chart (dR Exp(dth), dp + dR dp', dv + dR dv') is reached at the end
//             of the interval by the exact linear map blockdiag(dR^T, dR^T, dR^T) at the
//             estimate: the per-step Jacobians of the two charts are similar under the
//             chart change at each step, so the products telescope.
//   tangent:  additive on xi = [theta, p, v], GTSAM's own chart; A_tt is a general 3x3.
//
// The covariance step is written through the few 3-vectors it is linear in (see
// PropagateBlocks): every 3x3 product is one of the step's maps applied to a 3x3 block
// of Sigma, the rest are scaled sums. Structure relied on: theta does not depend on the
// accelerometer (so cov(dtheta, dba) and d theta/d ba stay zero), and isotropic noise
// (ImuNoise holds scalar densities), which keeps the bias block of Sigma at
// t * diag(q_a^2 I, q_g^2 I), makes N N^T = I and gives C C^T in closed form.
//
// Speed. The recursion runs on 3x3 blocks held as three 4-lane columns (simd_block3.h). The
// interval drivers (interval.h) run it once per held knot; each instruction set compiles
// them in its own translation unit (instance_*.cpp), and dispatch.cpp picks one per call
// from the CPU it runs on. Nothing in the per-sample loop touches the heap.
#pragma once

#include <cmath>

#include "imuconv/kernels/common.h"
#include "imuconv/kernels/preintegration.h"
#include "simd_pair.h"
#include "so3_fast.h"

IMUCONV_KERNEL_BEGIN

using simd::B;
using simd::BB;
using simd::d4;

/// The recursion's state, in 3x3 blocks (W: the pair type of the instance):
///   P = cov(delta x9) by its lower blocks (cov(row, column) for rows/columns theta, p, v),
///       column theta's p and v blocks side by side;
///   X = cov(delta x9, delta b), bias columns a (ba) and g (bg); the theta rows of the a
///       columns stay zero (theta does not see the accelerometer);
///   H = d x9 / d(ba, bg), same block pattern as X;
///   S = diag(s_ba I3, s_bg I3): with isotropic random walks and zero initial bias
///       uncertainty the bias block is exactly the accumulated random walk.
/// X and H follow the same recursion (X' = A X + Fb S, H' = A H - Fb) and are kept side
/// by side, [X_rc | H_rc] for row block r and bias column c.
template <class W>
struct State {
  B Ptt;
  BB<W> Ppvt;  ///< [Ppt | Pvt]
  B Ppp, Pvp, Pvv;
  BB<W> tg, pg, vg, pa, va;  ///< [X | H] blocks
  double s_ba, s_bg;
};

/// The state in plain blocks, as the interval drivers return it.
struct Blocks {
  B Ptt, Ppt, Pvt, Ppp, Pvp, Pvv;
  B Xpa, Xva, Xtg, Xpg, Xvg;
  B Hpa, Hva, Htg, Hpg, Hvg;
  double s_ba, s_bg;
};

template <class W>
IMUCONV_KERNEL_INLINE Blocks ToBlocks(const State<W>& s) {
  using simd::Hi;
  using simd::Lo;
  return {s.Ptt,    Lo(s.Ppvt), Hi(s.Ppvt), s.Ppp,    s.Pvp,    s.Pvv,
          Lo(s.pa), Lo(s.va),   Lo(s.tg),   Lo(s.pg), Lo(s.vg), Hi(s.pa),
          Hi(s.va), Hi(s.tg),   Hi(s.pg),   Hi(s.vg), s.s_ba,   s.s_bg};
}

template <class W>
IMUCONV_KERNEL_INLINE void ZeroState(State<W>& s) {
  const B z = simd::Zero();
  const BB<W> zz = simd::Pair<W>(z, z);
  s = State<W>{z, zz, z, z, z, zz, zz, zz, zz, zz, 0.0, 0.0};
}

/// Everything one step broadcasts, kept in memory (InMemory) so that the broadcasts are
/// loads: the maps N, C = C_t and dt N with [N | N] and [C | C]; C C^T = dt^2 (I + cc_g
/// [cc_u]x^2) in closed form; the step's scalars; b = dt R acc for the manifold chart.
template <class W>
struct StepConsts {
  B N, C, dtN;
  BB<W> dN, dC;
  d4 cc_u, b;
  double dt, hd, h, hd2, dt2, neg_dt, neg_h, one, neg_one;
  double s_bg, hs_ba, dts_ba;  // random-walk variances scaled
  double gg_outer, gg_diag;    // cov(g, g) = gg_diag I + gg_outer u u^T
  double h2kw, dthkw, dt2kw;   // cov(w, w) entering p'p', v'p', v'v'
  double s_ba_next, s_bg_next;
};

/// Fills the scalars (the maps N, C, cc_g, cc_u must be set), then pins everything in
/// memory and forms the pairs from there.
template <bool kCovariance, class W>
IMUCONV_KERNEL_INLINE void FinishStepConsts(StepConsts<W>& m, double dt, double cc_g,
                                            const NoiseVariances& q, double s_ba, double s_bg) {
  m.dt = dt;
  m.hd = 0.5 * dt;
  m.h = 0.5 * dt * dt;
  m.hd2 = m.hd * m.hd;
  m.dt2 = dt * dt;
  m.neg_dt = -dt;
  m.neg_h = -m.h;
  m.one = 1.0;
  m.neg_one = -1.0;
  m.dtN = dt * m.N;
  if constexpr (kCovariance) {
    const double inv_dt = 1.0 / dt;
    const double kw = s_ba + q.accel * inv_dt;  // cov(w, w) = kw I (N is a rotation)
    const double kg = s_bg + q.gyro * inv_dt;   // cov(g, g) = kg C C^T
    const double kcc = kg * dt * dt;
    m.s_bg = s_bg;
    m.hs_ba = m.h * s_ba;
    m.dts_ba = dt * s_ba;
    m.gg_outer = kcc * cc_g;
    m.gg_diag = kcc * (1.0 - cc_g * simd::Dot(m.cc_u, m.cc_u));
    m.h2kw = m.h * m.h * kw;
    m.dthkw = dt * m.h * kw;
    m.dt2kw = dt * dt * kw;
    m.s_ba_next = s_ba + dt * q.accel_walk;
    m.s_bg_next = s_bg + dt * q.gyro_walk;
  } else {  // without the covariance X stays zero and the variances are not tracked
    m.s_bg = m.hs_ba = m.dts_ba = 0.0;
  }
  simd::InMemory(m);
  m.dN = simd::Pair<W>(m.N, m.N);
  m.dC = simd::Pair<W>(m.C, m.C);
}

/// Start-frame chart of the manifold scheme: A_tt = I, K = -[b]x with b = dt dR acc
/// (read from the step's constants in memory).
template <class W>
struct StartFrameTransition {
  static constexpr bool kGeneral = false;
  d4 b, b1;          // b and its lanes rotated (cross products)
  d4 b0s, b1s, b2s;  // b's entries broadcast
  W w0, w1, w2;      // ... over both halves
  W wb, wb1;         // [b | b], rotated
  explicit StartFrameTransition(const d4& mb) {
    using O = simd::PairOps<W>;
    b = mb;
    b1 = simd::Yzx(mb);
    b0s = simd::Splat(mb[0]);
    b1s = simd::Splat(mb[1]);
    b2s = simd::Splat(mb[2]);
    w0 = O::Splat(mb[0]);
    w1 = O::Splat(mb[1]);
    w2 = O::Splat(mb[2]);
    wb = O::Cat(mb, mb);
    wb1 = O::Yzx(wb);
  }
  /// K z = z x b, column by column.
  IMUCONV_KERNEL_INLINE B LeftK(const B& z) const {
    B r;
    for (int j = 0; j < 3; ++j) r.c[j] = simd::Yzx(z.c[j] * b1 - simd::Yzx(z.c[j]) * b);
    return r;
  }
  IMUCONV_KERNEL_INLINE BB<W> LeftK(const BB<W>& z) const {
    using O = simd::PairOps<W>;
    BB<W> r;
    for (int j = 0; j < 3; ++j) r.c[j] = O::Yzx(z.c[j] * wb1 - O::Yzx(z.c[j]) * wb);
    return r;
  }
  /// z A_tt^T and z K^T = z [b]x.
  IMUCONV_KERNEL_INLINE void Right(const B& z, B& za, B& zk) const {
    za = z;
    zk = simd::TimesSkew(z, b0s, b1s, b2s);
  }
  IMUCONV_KERNEL_INLINE void Right(const BB<W>& z, BB<W>& za, BB<W>& zk) const {
    za = z;
    zk = simd::TimesSkew(z, w0, w1, w2);
  }
  /// A_tt Yt, K Yt, K Zt: here Tt = Ptt, Ut = K Ptt, Uu = K Ptt K^T = Ut [b]x.
  IMUCONV_KERNEL_INLINE void Left(const B& yt, const B&, B& tt, B& ut, B& uu) const {
    tt = yt;
    ut = LeftK(yt);
    uu = simd::TimesSkew(ut, b0s, b1s, b2s);
  }
  /// A_tt [X | H]_tg and K [X | H]_tg.
  IMUCONV_KERNEL_INLINE void LeftBias(const BB<W>& z, BB<W>& az, BB<W>& kz) const {
    az = z;
    kz = LeftK(z);
  }
};

/// General A_tt and K (tangent scheme), in memory for the broadcasts, with [A | K],
/// [A | A] and [K | K] for the pair products.
template <class W>
struct GeneralTransition {
  static constexpr bool kGeneral = true;
  B A, K;
  BB<W> AK, dA, dK;
  IMUCONV_KERNEL_INLINE void Right(const B& z, B& za, B& zk) const {
    za = simd::MulT(z, A);
    zk = simd::MulT(z, K);
  }
  IMUCONV_KERNEL_INLINE void Right(const BB<W>& z, BB<W>& za, BB<W>& zk) const {
    za = simd::MulT(z, A);
    zk = simd::MulT(z, K);
  }
  IMUCONV_KERNEL_INLINE void Left(const B& yt, const B& zt, B& tt, B& ut, B& uu) const {
    const BB<W> tu = simd::MulPair(AK, yt);  // [A Yt | K Yt]
    tt = simd::Lo(tu);
    ut = simd::Hi(tu);
    uu = simd::Mul(K, zt);
  }
  IMUCONV_KERNEL_INLINE void LeftBias(const BB<W>& z, BB<W>& az, BB<W>& kz) const {
    az = simd::MulDup(dA, z);
    kz = simd::MulDup(dK, z);
  }
};

/// One step of Sigma' = F Sigma F^T + G Q G^T (see the header comment) and of the bias
/// Jacobians, from `in` to `out`, in 3x3 blocks.
///
/// The step is written through the 3-vectors it is linear in:
///   theta~ = A_tt theta,  u = K theta,  g = C_t (db_g + n_g),  w = N (db_a + n_a),
///   q = p + dt v,
///   theta' = theta~ + g,  p' = q + (dt/2) u + (dt^2/2) w,  v' = v + u + dt w,
/// so that every 3x3 product is one of the maps A_tt, K (from the left or, transposed,
/// from the right), C_t or N applied to a block. With the noise and the bias block
/// isotropic, cov(w, w) = (s_ba + s_a^2/dt) I, and g is correlated with the state only
/// through the bias columns of X; w is uncorrelated with theta (cov(dtheta, dba) = 0).
/// PreintegratedImuMeasurements' 9x9 covariance is P of this recursion run with zero
/// random walk (X and the bias block then stay zero).
template <bool kCovariance, class W, class Transition>
IMUCONV_KERNEL_INLINE void PropagateBlocks(const Transition& tr, const StepConsts<W>& m,
                                           const State<W>& __restrict in,
                                           State<W>& __restrict out) {
  using namespace simd;
  using O = PairOps<W>;

  // [X | H] through the step: X' = A X + Fb S, H' = A H - Fb, with the rows of q = p + dt v
  // and of p' and v' before the inputs enter.
  BB<W> a_tg, k_tg;
  tr.LeftBias(in.tg, a_tg, k_tg);
  const BB<W> qa = AddScaled(in.pa, O::Splat(m.dt), in.va);  // [X | H]_qa
  const BB<W> gp =
      AddScaled(AddScaled(in.pg, O::Splat(m.dt), in.vg), O::Splat(m.hd), k_tg);  // q + dt/2 u vs bg
  const BB<W> gv = in.vg + k_tg;                                                 // v + u vs bg
  out.tg = AddScaled(a_tg, O::Cat(Splat(m.s_bg), Splat(m.neg_one)), m.dC);
  out.pg = gp;
  out.vg = gv;
  out.pa = AddScaled(qa, O::Cat(Splat(m.hs_ba), Splat(m.neg_h)), m.dN);
  out.va = AddScaled(in.va, O::Cat(Splat(m.dts_ba), Splat(m.neg_dt)), m.dN);
  if constexpr (!kCovariance) return;
  out.s_ba = m.s_ba_next;
  out.s_bg = m.s_bg_next;

  // Column theta of P: Yt = cov(theta, theta~), Zt = cov(theta, u), and for q and v
  // side by side; then Tt = cov(theta~, theta~), Ut = cov(u, theta~), Uu = cov(u, u).
  BB<W> Pqv;  // [cov(q, theta) | cov(v, theta)]
  for (int j = 0; j < 3; ++j) Pqv.c[j] = in.Ppvt.c[j] + O::Splat(m.dt) * O::ShiftDown(in.Ppvt.c[j]);
  B Yt, Zt, Tt, Ut, Uu;
  tr.Right(in.Ptt, Yt, Zt);
  if constexpr (Transition::kGeneral) {  // broadcast by the left products: from memory
    InMemory(Yt);
    InMemory(Zt);
  }
  tr.Left(Yt, Zt, Tt, Ut, Uu);
  InMemory(Ut);
  BB<W> Yqv, Zqv;
  tr.Right(Pqv, Yqv, Zqv);

  // cov(., g): Gt = cov(theta~, g) and [cov(q + dt/2 u, g) | cov(v + u, g)]; then P's
  // column theta. cov(g, g) = gg_diag I + gg_outer u u^T.
  {
    const B Gt = MulT(Lo(a_tg), m.C);
    const d4 gu = Splat(m.gg_outer) * m.cc_u;
    const B GG{{gu * Splat(m.cc_u[0]) + Splat(m.gg_diag) * kE0,
                gu * Splat(m.cc_u[1]) + Splat(m.gg_diag) * kE1,
                gu * Splat(m.cc_u[2]) + Splat(m.gg_diag) * kE2}};
    out.Ptt = Tt + Gt + Transpose(Gt) + GG;
  }
  {
    const BB<W> dUt = Pair<W>(Ut, Ut);
    const BB<W> gpv{{O::Los(gp.c[0], gv.c[0]), O::Los(gp.c[1], gv.c[1]), O::Los(gp.c[2], gv.c[2])}};
    out.Ppvt = MulTAdd(AddScaled(Yqv, O::Cat(Splat(m.hd), Splat(m.one)), dUt), gpv, m.C);
  }
  // [Rq | Sv] = [cov(q, u + dt w) | cov(v, u + dt w)] with cov(., w) = X_.a N^T; the
  // symmetric diagonal blocks are each a block plus its transpose.
  const BB<W> qva{
      {O::Los(qa.c[0], in.va.c[0]), O::Los(qa.c[1], in.va.c[1]), O::Los(qa.c[2], in.va.c[2])}};
  const BB<W> RS = MulTAdd(Zqv, qva, m.dtN);
  const B Rq = Lo(RS), Sv = Hi(RS);
  const B Spp = AddScaled(m.hd * Rq, m.dt, in.Pvp);
  out.Ppp = AddDiagonal(
      AddScaled(AddScaled(in.Ppp, m.dt2, in.Pvv), m.hd2, Uu) + Spp + Transpose(Spp), m.h2kw);
  out.Pvp = AddDiagonal(
      AddScaled(AddScaled(AddScaled(in.Pvp, m.dt, in.Pvv), m.hd, Sv), m.hd, Uu) + Transpose(Rq),
      m.dthkw);
  out.Pvv = AddDiagonal(in.Pvv + Uu + Sv + Transpose(Sv), m.dt2kw);
}

// ---------------------------------------------------------------------------------------
// Assembly of the outputs (once per interval).

/// The 15x15 covariance [P X; X^T S] in the kernel's chart, exactly symmetric.
inline Mat15 AssembleCovariance(const Blocks& c) {
  Mat15 S = Mat15::Zero();
  const auto put = [&S](int i, int j, const B& m) {
    simd::ToEigen(m, S.block<3, 3>(3 * i, 3 * j));
  };
  put(0, 0, c.Ptt);
  put(1, 0, c.Ppt);
  put(2, 0, c.Pvt);
  put(1, 1, c.Ppp);
  put(2, 1, c.Pvp);
  put(2, 2, c.Pvv);
  put(1, 3, c.Xpa);
  put(2, 3, c.Xva);
  put(0, 4, c.Xtg);
  put(1, 4, c.Xpg);
  put(2, 4, c.Xvg);
  S.block<3, 3>(9, 9).diagonal().setConstant(c.s_ba);
  S.block<3, 3>(12, 12).diagonal().setConstant(c.s_bg);
  // P's lower blocks and X's blocks are each stored once: mirror them. P's diagonal
  // blocks are symmetric in exact arithmetic, not in rounding: average them.
  for (int j = 0; j < 15; ++j)
    for (int i = j + 1; i < 15; ++i) {
      if (i < 9 && i / 3 == j / 3) {
        S(i, j) = S(j, i) = 0.5 * (S(i, j) + S(j, i));
      } else if (j < 9) {
        S(i, j) = S(j, i) = S(i, j) + S(j, i);  // exactly one of the two was written
      }
    }
  return S;
}

/// 9x6 bias Jacobian, columns [ba, bg] (GTSAM's layout), in the kernel's chart.
inline Mat96 AssembleBiasJacobian(const Blocks& c) {
  Mat96 J = Mat96::Zero();
  simd::ToEigen(c.Hpa, J.block<3, 3>(3, 0));
  simd::ToEigen(c.Hva, J.block<3, 3>(6, 0));
  simd::ToEigen(c.Htg, J.block<3, 3>(0, 3));
  simd::ToEigen(c.Hpg, J.block<3, 3>(3, 3));
  simd::ToEigen(c.Hvg, J.block<3, 3>(6, 3));
  return J;
}

IMUCONV_KERNEL_END
