// The interval drivers of the preintegration kernel: the held knots of a window, one step
// of each scheme over the SIMD block state (block_recursion.h), and the whole interval.
// Compiled once per instruction set (instance_*.cpp), each with its own pair type W.
#pragma once

#include <cmath>

#include "block_recursion.h"

#ifndef IMUCONV_KERNEL_TARGET
#define IMUCONV_KERNEL_TARGET
#endif
#include "imuconv/preintegrator.h"
#include "imuconv/window.h"

IMUCONV_KERNEL_BEGIN

/// The held knots of the window, in order: knot j (bias-corrected with (bg, ba)) is held
/// over [t_j, t_j+1].
struct HeldKnots {
  const SampleWindow& w;
  d4 ba, bg;
  std::size_t steps() const { return w.size() - 1; }
  IMUCONV_KERNEL_INLINE const ImuSample& knot(std::size_t j) const {
    return j == 0 ? w.first : w.samples[w.begin + j - 1];
  }
  IMUCONV_KERNEL_INLINE double t_next(std::size_t j) const {
    return j + 2 == w.size() ? w.last.t : w.samples[w.begin + j].t;
  }
  IMUCONV_KERNEL_INLINE const ImuSample& next_knot(std::size_t j) const {
    return j + 2 == w.size() ? w.last : w.samples[w.begin + j];
  }
  /// The value held over [t_j, t_j+1]: knot j (zero-order hold, GTSAM's input) or, with
  /// kMidpoint, the mean of knots j and j+1 (OpenVINS' imu_avg; the midpoint propagator's
  /// input, see kernels/euler.h), formed in `tmp`.
  template <bool kMidpoint>
  IMUCONV_KERNEL_INLINE const ImuSample& held(std::size_t j, ImuSample& tmp) const {
    if constexpr (!kMidpoint) {
      (void)tmp;
      return knot(j);
    } else {
      const ImuSample& a = knot(j);
      const ImuSample& b = next_knot(j);
      tmp.t = a.t;
      tmp.gyro = 0.5 * (a.gyro + b.gyro);
      tmp.accel = 0.5 * (a.accel + b.accel);
      return tmp;
    }
  }
};

/// Runs step(knot, dt_j, in, out) over the window, alternating the two state buffers;
/// returns the buffer holding the result.
template <class W, bool kMidpoint = false, typename StepFn>
IMUCONV_KERNEL_INLINE const State<W>& RunHeldKnots(const PreintegrationInput& in, State<W>& b0,
                                                   State<W>& b1, StepFn& step) {
  const HeldKnots knots{in.window, simd::FromEigen(in.ba), simd::FromEigen(in.bg)};
  const std::size_t steps = knots.steps();
  ImuSample tmp;
  std::size_t j = 0;
#if IMUCONV_KERNEL_NARROW
  // One step per iteration, the buffers swapped by pointer. On a 128-bit target a step is
  // about 2000 (manifold) to 3000 (tangent) instructions; with two copies per iteration, as
  // below, the tangent ran at half this speed for the same instruction count (SSE2 on the
  // EPYC; a loop of ~30 KB of code, beyond the cores' decoded-instruction caches, is the
  // likely cause).
  State<W>* cur = &b0;
  State<W>* next = &b1;
  for (; j < steps; ++j) {
    const ImuSample& s = knots.held<kMidpoint>(j, tmp);
    step(s, knots.t_next(j) - s.t, *cur, *next);
    State<W>* const t = cur;
    cur = next;
    next = t;
  }
  return *cur;
#else
  for (; j + 1 < steps; j += 2) {
    const ImuSample& s0 = knots.held<kMidpoint>(j, tmp);
    step(s0, knots.t_next(j) - s0.t, b0, b1);
    const ImuSample& s1 = knots.held<kMidpoint>(j + 1, tmp);
    step(s1, knots.t_next(j + 1) - s1.t, b1, b0);
  }
  if (j < steps) {
    const ImuSample& s0 = knots.held<kMidpoint>(j, tmp);
    step(s0, knots.t_next(j) - s0.t, b0, b1);
    return b1;
  }
  return b0;
#endif
}

/// Bias-corrected inputs of a sample, as vectors and as broadcast entries (loads from the
/// sample minus the broadcast bias).
struct Inputs {
  d4 ba[3], bg[3], ba_v, bg_v;
  explicit Inputs(const PreintegrationInput& in) {
    for (int k = 0; k < 3; ++k) {
      ba[k] = simd::Splat(in.ba[k]);
      bg[k] = simd::Splat(in.bg[k]);
    }
    ba_v = simd::FromEigen(in.ba);
    bg_v = simd::FromEigen(in.bg);
  }
  IMUCONV_KERNEL_INLINE d4 acc(const ImuSample& s) const {
    return simd::Load3(s.accel.data()) - ba_v;
  }
  IMUCONV_KERNEL_INLINE d4 omega(const ImuSample& s) const {
    return simd::Load3(s.gyro.data()) - bg_v;
  }
  IMUCONV_KERNEL_INLINE d4 acc(const ImuSample& s, int k) const {
    return simd::Splat(s.accel.data()[k]) - ba[k];
  }
  IMUCONV_KERNEL_INLINE d4 omega(const ImuSample& s, int k) const {
    return simd::Splat(s.gyro.data()[k]) - bg[k];
  }
};

/// One manifold step (start-frame chart) as a functor over the state buffers.
template <bool kCovariance, class W>
struct ManifoldStepper {
  NoiseVariances q;
  Inputs u;
  B dR;
  d4 dp, dv;
  double dt_total;

  IMUCONV_KERNEL_INLINE void operator()(const ImuSample& s, double dt,
                                        const State<W>& __restrict in, State<W>& __restrict out) {
    using namespace simd;
    const d4 vdt = Splat(dt);
    const d4 phi = vdt * u.omega(s);
    const double t2 = Dot(phi, phi);
    ExpJrCoefs k;
    if (t2 < so3::detail::kSeriesBelow * so3::detail::kSeriesBelow) {
      k = ExpJrSeries(t2);
    } else {
      const double t = std::sqrt(t2);
      double sh, ch;
      SinCosNonNegative(0.5 * t, sh, ch);
      k = ExpJrClosed(t, 1.0 / t2, sh, ch);
    }
    // dR Exp(phi) = dR + a T1 + b T2 and dR Jl(phi) = dR + b T1 + c T2 with
    // T1 = dR [phi]x, T2 = dR [phi]x^2: no 3x3 product.
    const d4 p0 = vdt * u.omega(s, 0), p1 = vdt * u.omega(s, 1), p2 = vdt * u.omega(s, 2);
    const B T1 = TimesSkew(dR, p0, p1, p2), T2 = TimesSkew(T1, p0, p1, p2);
    const d4 a_start = dR.c[0] * u.acc(s, 0) + dR.c[1] * u.acc(s, 1) + dR.c[2] * u.acc(s, 2);

    StepConsts<W> m;
    m.N = dR;
    m.C = AddScaled(AddScaled(dt * dR, dt * k.b, T1), dt * k.c, T2);  // dt dR Jl(phi)
    m.cc_u = dR.c[0] * p0 + dR.c[1] * p1 + dR.c[2] * p2;  // dR Jl Jl^T dR^T = I + g [dR phi]x^2
    m.b = vdt * a_start;
    FinishStepConsts<kCovariance>(m, dt, SymmetricSquareCoef(k.b, k.c, t2), q, in.s_ba, in.s_bg);
    PropagateBlocks<kCovariance>(StartFrameTransition<W>(m.b), m, in, out);

    dp += vdt * dv + Splat(0.5 * dt * dt) * a_start;
    dv += vdt * a_start;
    dR = AddScaled(AddScaled(dR, k.a, T1), k.b, T2);
    dt_total += dt;
  }
};

/// Manifold scheme over the window, start-frame chart; kMidpoint holds the mean of
/// adjacent knots instead of knot j (see HeldKnots::held).
template <bool kCovariance, class W, bool kMidpoint = false>
IMUCONV_KERNEL_INLINE void ManifoldInterval(const PreintegrationInput& in, ManifoldIncrement& inc,
                                            Blocks& result) {
  using namespace simd;
  State<W> b0, b1;
  ZeroState(b0);
  ManifoldStepper<kCovariance, W> step{
      NoiseVariances(in.noise), Inputs(in), Identity(), Splat(0.0), Splat(0.0), 0.0};
  result = ToBlocks(RunHeldKnots<W, kMidpoint>(in, b0, b1, step));
  inc.dt = step.dt_total;
  ToEigen(step.dR, inc.dR);
  inc.dp = ToEigen(step.dp);
  inc.dv = ToEigen(step.dv);
}

/// The tangent step's vectors whose entries are broadcast, kept in memory.
struct TangentVectors {
  d4 theta, dw, ev;
};

/// One tangent step (additive chart of xi) as a functor over the state buffers.
template <bool kCovariance, class W>
struct TangentStepper {
  NoiseVariances q;
  Inputs u;
  d4 theta, p, v;
  double dt_total;

  IMUCONV_KERNEL_INLINE void operator()(const ImuSample& s, double dt,
                                        const State<W>& __restrict in, State<W>& __restrict out) {
    using namespace simd;
    const d4 vdt = Splat(dt);
    const d4 omega = u.omega(s), acc = u.acc(s);
    const d4 th = theta;
    const double t2 = Dot(th, th);
    TangentCoefs c;
    if (t2 < kTangentSeriesBelow * kTangentSeriesBelow) {
      c.d = JrInvSeriesD(t2);  // the only coefficient theta' needs: keep it first
      const d4 abce = TangentSeriesABCE(t2);
      c.a = abce[0];
      c.b = abce[1];
      c.c = abce[2];
      c.e = abce[3];
    } else {
      c = TangentClosed(std::sqrt(t2), t2);
    }
    // theta' = theta + dt Jr^{-1}(theta) omega, with
    // Jr^{-1} omega = omega + 1/2 theta x omega + d theta x (theta x omega).
    const double tw = Dot(th, omega);
    const d4 txtxw = th * Splat(tw) - omega * Splat(t2);
    theta = th + vdt * (omega + Splat(0.5) * Cross(th, omega) + Splat(c.d) * txtxw);

    // R acc = acc + a theta x acc + b theta x (theta x acc).
    const d4 a_start =
        Splat(1.0 - c.b * t2) * acc + Splat(c.a) * Cross(th, acc) + Splat(c.b * Dot(th, acc)) * th;

    TangentVectors tv{th, Splat(dt * c.d) * omega, {}};
    tv.ev = Splat(dt * c.e) * txtxw - Splat(2.0) * tv.dw;
    InMemory(tv);
    // theta's [.]x and theta theta^T, by columns (entries broadcast from memory).
    const So3Basis basis{
        Skew(th), {{th * Splat(tv.theta[0]), th * Splat(tv.theta[1]), th * Splat(tv.theta[2])}}};
    StepConsts<W> m;
    m.N = Poly(basis, 1.0 - c.b * t2, c.a, c.b);                   // R
    m.C = Poly(basis, dt * (1.0 - c.d * t2), 0.5 * dt, dt * c.d);  // dt Jr^{-1}
    m.cc_u = th;  // Jr^{-1} Jr^{-T} = I + g [theta]x^2
    FinishStepConsts<kCovariance>(m, dt, SymmetricSquareCoef(0.5, c.d, t2), q, in.s_ba, in.s_bg);
    GeneralTransition<W> tr;  // kept in memory: its entries are broadcast
    // K = -dt [R acc]x Jl(theta): the columns of Jl crossed with dt R acc.
    {
      const B Jl = Poly(basis, 1.0 - c.c * t2, c.b, c.c);
      const d4 bk = vdt * a_start, bk1 = Yzx(bk);
      for (int j = 0; j < 3; ++j) tr.K.c[j] = Yzx(Jl.c[j] * bk1 - Yzx(Jl.c[j]) * bk);
    }
    // A_tt = I + dt D, D = (d theta.omega) I - 1/2 [omega]x + theta (d omega)^T
    //                      + (e theta x (theta x omega) - 2 d omega) theta^T.
    {
      const d4 a0 = Splat(1.0 + dt * c.d * tw);
      const B w = Skew(Splat(-0.5 * dt) * omega);
      tr.A.c[0] = a0 * kE0 + w.c[0] + th * Splat(tv.dw[0]) + tv.ev * Splat(tv.theta[0]);
      tr.A.c[1] = a0 * kE1 + w.c[1] + th * Splat(tv.dw[1]) + tv.ev * Splat(tv.theta[1]);
      tr.A.c[2] = a0 * kE2 + w.c[2] + th * Splat(tv.dw[2]) + tv.ev * Splat(tv.theta[2]);
    }
    InMemory(tr.A);
    InMemory(tr.K);
    tr.AK = Pair<W>(tr.A, tr.K);
    tr.dA = Pair<W>(tr.A, tr.A);
    tr.dK = Pair<W>(tr.K, tr.K);
    PropagateBlocks<kCovariance>(tr, m, in, out);

    p += vdt * v + Splat(0.5 * dt * dt) * a_start;
    v += vdt * a_start;
    dt_total += dt;
  }
};

/// Tangent scheme over the window, additive chart of xi.
template <bool kCovariance, class W>
IMUCONV_KERNEL_INLINE void TangentInterval(const PreintegrationInput& in, TangentIncrement& inc,
                                           Blocks& result) {
  using namespace simd;
  State<W> b0, b1;
  ZeroState(b0);
  TangentStepper<kCovariance, W> step{
      NoiseVariances(in.noise), Inputs(in), Splat(0.0), Splat(0.0), Splat(0.0), 0.0};
  result = ToBlocks(RunHeldKnots(in, b0, b1, step));
  inc.dt = step.dt_total;
  for (int k = 0; k < 3; ++k) {
    inc.xi(k) = step.theta[k];
    inc.xi(3 + k) = step.p[k];
    inc.xi(6 + k) = step.v[k];
  }
}

// ---- The entry points of one instance (see instances.h): the interval, then the
// blocks assembled into Eigen matrices in the kernel's own chart (copies and sums only,
// so the instruction set cannot change them).
//
// The interval variants are the instance's only functions compiled for its instruction set
// (IMUCONV_KERNEL_TARGET, set by instance_*.cpp): see kernel_config.h for why that is a
// target attribute on these few functions rather than a flag for the whole file.

template <bool kCovariance, class W, bool kMidpoint>
IMUCONV_KERNEL_TARGET __attribute__((noinline)) void ManifoldIntervalOf(
    const PreintegrationInput& in, ManifoldIncrement& inc, Blocks& result) {
  ManifoldInterval<kCovariance, W, kMidpoint>(in, inc, result);
}
template <bool kCovariance, class W>
IMUCONV_KERNEL_TARGET __attribute__((noinline)) void TangentIntervalOf(
    const PreintegrationInput& in, TangentIncrement& inc, Blocks& result) {
  TangentInterval<kCovariance, W>(in, inc, result);
}

template <class W>
void RunManifoldInstance(const PreintegrationInput& in, Hold hold, ManifoldIncrement& inc,
                         Mat96& J_inc_bias, Mat15* cov) {
  Blocks r;
  if (cov) {
    if (hold == Hold::Midpoint)
      ManifoldIntervalOf<true, W, true>(in, inc, r);
    else
      ManifoldIntervalOf<true, W, false>(in, inc, r);
    *cov = AssembleCovariance(r);
  } else {
    if (hold == Hold::Midpoint)
      ManifoldIntervalOf<false, W, true>(in, inc, r);
    else
      ManifoldIntervalOf<false, W, false>(in, inc, r);
  }
  J_inc_bias = AssembleBiasJacobian(r);
}

template <class W>
void RunTangentInstance(const PreintegrationInput& in, TangentIncrement& inc, Mat96& J_inc_bias,
                        Mat15* cov) {
  Blocks r;
  if (cov) {
    TangentIntervalOf<true, W>(in, inc, r);
    *cov = AssembleCovariance(r);
  } else {
    TangentIntervalOf<false, W>(in, inc, r);
  }
  J_inc_bias = AssembleBiasJacobian(r);
}

IMUCONV_KERNEL_END
