// 3x3 blocks as three 4-lane columns (GCC/Clang vector extensions), the arithmetic of the
// preintegration kernel's block recursion (block_recursion.h). Lane 3 of every column is
// padding and stays zero. Included only by the kernel's own translation units: the 4-lane
// values passed between these always-inline helpers would change the ABI of any function
// that took them by value out of line (GCC's -Wpsabi note), and none is ever emitted so.
#pragma once

#include "kernel_config.h"

#if !IMUCONV_KERNEL_HAS_VECTORS
#error \
    "simd_block3.h needs GCC or Clang vector extensions; other compilers use the portable path only"
#endif

#include "imuconv/types.h"

IMUCONV_KERNEL_BEGIN
namespace simd {

#if IMUCONV_KERNEL_NARROW
/// 2 doubles: one register of a 128-bit target (SSE2, NEON).
typedef double d2 __attribute__((vector_size(16)));
/// 4 doubles as two native 2-lane halves; 3-vectors use lanes 0-2 and keep lane 3 zero.
/// Why not the 32-byte vector type here: a target without 256-bit registers gives it no
/// machine mode, so GCC 12 keeps every such value in a stack slot and builds its splats and
/// lane shuffles there element by element (stores of 8 bytes read back as 16: store-to-load
/// forwarding fails). Two 2-lane members are two registers, and each shuffle below is one or
/// two 2-lane shuffles. The lanes' arithmetic is the same, operation by operation.
struct d4 {
  d2 lo, hi;
  constexpr d4() : lo{}, hi{} {}
  constexpr d4(double a, double b, double c, double d) : lo{a, b}, hi{c, d} {}
  constexpr d4(const d2& l, const d2& h) : lo(l), hi(h) {}
  IMUCONV_KERNEL_INLINE double operator[](int k) const { return k < 2 ? lo[k] : hi[k - 2]; }
  IMUCONV_KERNEL_INLINE d4& operator+=(const d4& b) {
    lo += b.lo;
    hi += b.hi;
    return *this;
  }
};
IMUCONV_KERNEL_INLINE d4 operator+(const d4& a, const d4& b) { return {a.lo + b.lo, a.hi + b.hi}; }
IMUCONV_KERNEL_INLINE d4 operator-(const d4& a, const d4& b) { return {a.lo - b.lo, a.hi - b.hi}; }
IMUCONV_KERNEL_INLINE d4 operator*(const d4& a, const d4& b) { return {a.lo * b.lo, a.hi * b.hi}; }
IMUCONV_KERNEL_INLINE d4 operator-(const d4& a) { return {-a.lo, -a.hi}; }

IMUCONV_KERNEL_INLINE d4 Splat(double x) {
  const d2 v = {x, x};
  return {v, v};
}
template <int k>
IMUCONV_KERNEL_INLINE d4 Lane(const d4& v) {
  const d2 h = k < 2 ? __builtin_shufflevector(v.lo, v.lo, k % 2, k % 2)
                     : __builtin_shufflevector(v.hi, v.hi, k % 2, k % 2);
  return {h, h};
}
/// (a1, a2, a0, a3).
IMUCONV_KERNEL_INLINE d4 Yzx(const d4& a) {
  return {__builtin_shufflevector(a.lo, a.hi, 1, 2), __builtin_shufflevector(a.lo, a.hi, 0, 3)};
}
#else
/// 4 doubles; 3-vectors use lanes 0-2 and keep lane 3 zero.
typedef double d4 __attribute__((vector_size(32)));

/// x in every lane. Written as a shuffle of lane 0: GCC 12 emits the plain initializer
/// {x, x, x, x} of a register as two instructions under the target attribute, this as one
/// vbroadcastsd (from memory when x is a load).
IMUCONV_KERNEL_INLINE d4 Splat(double x) {
  const d4 v = {x, 0.0, 0.0, 0.0};
  return __builtin_shufflevector(v, v, 0, 0, 0, 0);
}
/// Lane k of v in every lane (one permute; Splat(v[k]) when v is in memory).
template <int k>
IMUCONV_KERNEL_INLINE d4 Lane(const d4& v) {
  return __builtin_shufflevector(v, v, k, k, k, k);
}
IMUCONV_KERNEL_INLINE d4 Yzx(const d4& a) { return __builtin_shufflevector(a, a, 1, 2, 0, 3); }
#endif
/// Column-major 3x3 block; lane 3 of every column is zero.
struct B {
  d4 c[3];
};
IMUCONV_KERNEL_INLINE d4 Load3(const double* p) { return d4{p[0], p[1], p[2], 0.0}; }
IMUCONV_KERNEL_INLINE d4 FromEigen(const Vec3& v) { return Load3(v.data()); }
IMUCONV_KERNEL_INLINE Vec3 ToEigen(const d4& v) { return Vec3(v[0], v[1], v[2]); }
IMUCONV_KERNEL_INLINE void ToEigen(
    const B& m, Eigen::Ref<Eigen::Matrix<double, 3, 3>, 0, Eigen::OuterStride<>> out) {
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) out(i, j) = m.c[j][i];
}

constexpr d4 kE0 = {1.0, 0.0, 0.0, 0.0}, kE1 = {0.0, 1.0, 0.0, 0.0}, kE2 = {0.0, 0.0, 1.0, 0.0};
IMUCONV_KERNEL_INLINE B Identity() { return {{kE0, kE1, kE2}}; }
IMUCONV_KERNEL_INLINE B Zero() { return {{Splat(0.0), Splat(0.0), Splat(0.0)}}; }

IMUCONV_KERNEL_INLINE B operator+(const B& a, const B& b) {
  return {{a.c[0] + b.c[0], a.c[1] + b.c[1], a.c[2] + b.c[2]}};
}
IMUCONV_KERNEL_INLINE B operator-(const B& a, const B& b) {
  return {{a.c[0] - b.c[0], a.c[1] - b.c[1], a.c[2] - b.c[2]}};
}
IMUCONV_KERNEL_INLINE B operator*(double s, const B& a) {
  const d4 v = Splat(s);
  return {{v * a.c[0], v * a.c[1], v * a.c[2]}};
}
/// a + s b.
IMUCONV_KERNEL_INLINE B AddScaled(const B& a, double s, const B& b) {
  const d4 v = Splat(s);
  return {{a.c[0] + v * b.c[0], a.c[1] + v * b.c[1], a.c[2] + v * b.c[2]}};
}
/// a + s I.
IMUCONV_KERNEL_INLINE B AddDiagonal(const B& a, double s) {
  const d4 v = Splat(s);
  return {{a.c[0] + v * kE0, a.c[1] + v * kE1, a.c[2] + v * kE2}};
}
IMUCONV_KERNEL_INLINE B Transpose(const B& a) {
#if IMUCONV_KERNEL_NARROW  // the same lanes as below: lane 3 of every column is a.c[2]'s lane 3
  const d2 &c0 = a.c[0].lo, &c1 = a.c[1].lo, &c2 = a.c[2].lo, &c0h = a.c[0].hi, &c1h = a.c[1].hi,
           &c2h = a.c[2].hi;
  return {{{__builtin_shufflevector(c0, c1, 0, 2), __builtin_shufflevector(c2, c2h, 0, 3)},
           {__builtin_shufflevector(c0, c1, 1, 3), __builtin_shufflevector(c2, c2h, 1, 3)},
           {__builtin_shufflevector(c0h, c1h, 0, 2), c2h}}};
#else
  const d4 lo = __builtin_shufflevector(a.c[0], a.c[1], 0, 4, 2, 6);  // a00 a01 a20 a21
  const d4 hi = __builtin_shufflevector(a.c[0], a.c[1], 1, 5, 3, 7);  // a10 a11 0 0
  return {{__builtin_shufflevector(lo, a.c[2], 0, 1, 4, 7),
           __builtin_shufflevector(hi, a.c[2], 0, 1, 5, 7),
           __builtin_shufflevector(lo, a.c[2], 2, 3, 6, 7)}};
#endif
}

// Products broadcast the entries of one factor and scale the columns of the other; the
// broadcast factor should sit in memory (state blocks, or InMemory below), so that the
// broadcasts are loads. The *Add forms accumulate into acc (FMAs only).
/// acc + a b.
IMUCONV_KERNEL_INLINE B MulAdd(const B& acc, const B& a, const B& b) {
  B r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = acc.c[j] + a.c[0] * Splat(b.c[j][0]) + a.c[1] * Splat(b.c[j][1]) +
             a.c[2] * Splat(b.c[j][2]);
  return r;
}
/// a b.
IMUCONV_KERNEL_INLINE B Mul(const B& a, const B& b) {
  B r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = a.c[0] * Splat(b.c[j][0]) + a.c[1] * Splat(b.c[j][1]) + a.c[2] * Splat(b.c[j][2]);
  return r;
}
/// acc + a b^T.
IMUCONV_KERNEL_INLINE B MulTAdd(const B& acc, const B& a, const B& b) {
  B r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = acc.c[j] + a.c[0] * Splat(b.c[0][j]) + a.c[1] * Splat(b.c[1][j]) +
             a.c[2] * Splat(b.c[2][j]);
  return r;
}
/// a b^T.
IMUCONV_KERNEL_INLINE B MulT(const B& a, const B& b) {
  B r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = a.c[0] * Splat(b.c[0][j]) + a.c[1] * Splat(b.c[1][j]) + a.c[2] * Splat(b.c[2][j]);
  return r;
}
/// a v (v in a register: lane permutes).
IMUCONV_KERNEL_INLINE d4 MulV(const B& a, const d4& v) {
  return a.c[0] * Lane<0>(v) + a.c[1] * Lane<1>(v) + a.c[2] * Lane<2>(v);
}

IMUCONV_KERNEL_INLINE double Dot(const d4& a, const d4& b) {
  const d4 p = a * b;
  return p[0] + p[1] + p[2];
}
/// a x b.
IMUCONV_KERNEL_INLINE d4 Cross(const d4& a, const d4& b) { return Yzx(a * Yzx(b) - Yzx(a) * b); }
/// z [b]x, with b's entries broadcast in b0, b1, b2.
IMUCONV_KERNEL_INLINE B TimesSkew(const B& z, const d4& b0, const d4& b1, const d4& b2) {
  return {{b2 * z.c[1] - b1 * z.c[2], b0 * z.c[2] - b2 * z.c[0], b1 * z.c[0] - b0 * z.c[1]}};
}
/// u v^T.
IMUCONV_KERNEL_INLINE B Outer(const d4& u, const d4& v) {
  return {{u * Lane<0>(v), u * Lane<1>(v), u * Lane<2>(v)}};
}

/// [w]x and w w^T by columns, for alpha I + beta [w]x + gamma w w^T (Exp, Jr, Jl, Jr^{-1}
/// of w, with [w]x^2 = w w^T - |w|^2 I).
struct So3Basis {
  B skew, outer;
};
/// [w]x by columns (lane 3 of w, zero, fills its zeros).
IMUCONV_KERNEL_INLINE B Skew(const d4& w) {
  const d4 m = -w;
#if IMUCONV_KERNEL_NARROW
  return {{{__builtin_shufflevector(w.hi, w.hi, 1, 0), __builtin_shufflevector(m.lo, w.hi, 1, 3)},
           {__builtin_shufflevector(m.hi, w.hi, 0, 3), __builtin_shufflevector(w.lo, w.hi, 0, 3)},
           {__builtin_shufflevector(w.lo, m.lo, 1, 2), __builtin_shufflevector(w.hi, w.hi, 1, 1)}}};
#else
  return {{__builtin_shufflevector(w, m, 3, 2, 5, 3), __builtin_shufflevector(w, m, 6, 3, 0, 3),
           __builtin_shufflevector(w, m, 1, 4, 3, 3)}};
#endif
}
IMUCONV_KERNEL_INLINE So3Basis MakeSo3Basis(const d4& w) { return {Skew(w), Outer(w, w)}; }
IMUCONV_KERNEL_INLINE B Poly(const So3Basis& s, double alpha, double beta, double gamma) {
  const d4 a = Splat(alpha), b = Splat(beta), g = Splat(gamma);
  return {{a * kE0 + b * s.skew.c[0] + g * s.outer.c[0],
           a * kE1 + b * s.skew.c[1] + g * s.outer.c[1],
           a * kE2 + b * s.skew.c[2] + g * s.outer.c[2]}};
}

/// Makes the compiler keep `x` in memory from here on, so that broadcasts of its entries
/// are loads (load ports) instead of lane shuffles. Not on a 128-bit target: SSE2 has no
/// broadcast load, so a broadcast is a shuffle either way, and pinning only added stores and
/// reloads (the SSE2 manifold step went from 145 to 120 ns/sample without it, EPYC).
template <typename T>
IMUCONV_KERNEL_INLINE void InMemory(T& x) {
#if !IMUCONV_KERNEL_NARROW
  asm volatile("" : "+m"(x));
#else
  (void)x;
#endif
}

}  // namespace simd
IMUCONV_KERNEL_END
