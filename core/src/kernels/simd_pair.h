// Pairs of 3x3 blocks side by side, for the block recursion (block_recursion.h): two 4-lane
// columns as one 8-lane vector under AVX-512 (d8), two 4-lane halves elsewhere (d4x2:
// without AVX-512, GCC lowers 8-lane shuffles through memory). The recursion is written
// once over the pair type W; each instance picks its W (instance_*.cpp).
#pragma once

#include "simd_block3.h"

IMUCONV_KERNEL_BEGIN
namespace simd {

#if !IMUCONV_KERNEL_NARROW
typedef double d8 __attribute__((vector_size(64)));
#endif
struct d4x2 {
  d4 lo, hi;
};
IMUCONV_KERNEL_INLINE d4x2 operator+(const d4x2& a, const d4x2& b) {
  return {a.lo + b.lo, a.hi + b.hi};
}
IMUCONV_KERNEL_INLINE d4x2 operator-(const d4x2& a, const d4x2& b) {
  return {a.lo - b.lo, a.hi - b.hi};
}
IMUCONV_KERNEL_INLINE d4x2 operator*(const d4x2& a, const d4x2& b) {
  return {a.lo * b.lo, a.hi * b.hi};
}
IMUCONV_KERNEL_INLINE d4x2 operator-(const d4x2& a) { return {-a.lo, -a.hi}; }

#if !IMUCONV_KERNEL_NARROW
IMUCONV_KERNEL_INLINE d4 Lo(const d8& x) { return __builtin_shufflevector(x, x, 0, 1, 2, 3); }
IMUCONV_KERNEL_INLINE d4 Hi(const d8& x) { return __builtin_shufflevector(x, x, 4, 5, 6, 7); }
#endif
IMUCONV_KERNEL_INLINE d4 Lo(const d4x2& x) { return x.lo; }
IMUCONV_KERNEL_INLINE d4 Hi(const d4x2& x) { return x.hi; }

template <class W>
struct PairOps;
#if !IMUCONV_KERNEL_NARROW
template <>
struct PairOps<d8> {
  static IMUCONV_KERNEL_INLINE d8 Cat(const d4& a, const d4& b) {
    return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7);
  }
  static IMUCONV_KERNEL_INLINE d8 Splat(double x) {
    const d8 v = {x, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    return __builtin_shufflevector(v, v, 0, 0, 0, 0, 0, 0, 0, 0);
  }
  /// [lane k of the first half x4 | lane k of the second half x4].
  template <int k>
  static IMUCONV_KERNEL_INLINE d8 Lane(const d8& x) {
    return __builtin_shufflevector(x, x, k, k, k, k, k + 4, k + 4, k + 4, k + 4);
  }
  static IMUCONV_KERNEL_INLINE d8 Yzx(const d8& x) {
    return __builtin_shufflevector(x, x, 1, 2, 0, 3, 5, 6, 4, 7);
  }
  /// [second half | 0].
  static IMUCONV_KERNEL_INLINE d8 ShiftDown(const d8& x) {
    const d8 z = {};
    return __builtin_shufflevector(x, z, 4, 5, 6, 7, 8, 8, 8, 8);
  }
  /// [first half of a | first half of b].
  static IMUCONV_KERNEL_INLINE d8 Los(const d8& a, const d8& b) {
    return __builtin_shufflevector(a, b, 0, 1, 2, 3, 8, 9, 10, 11);
  }
  /// [second half of a | second half of a].
  static IMUCONV_KERNEL_INLINE d8 DupHi(const d8& a) {
    return __builtin_shufflevector(a, a, 4, 5, 6, 7, 4, 5, 6, 7);
  }
};
#endif
template <>
struct PairOps<d4x2> {
  static IMUCONV_KERNEL_INLINE d4x2 Cat(const d4& a, const d4& b) { return {a, b}; }
  static IMUCONV_KERNEL_INLINE d4x2 Splat(double x) {
    const d4 v = simd::Splat(x);
    return {v, v};
  }
  template <int k>
  static IMUCONV_KERNEL_INLINE d4x2 Lane(const d4x2& x) {
    return {simd::Lane<k>(x.lo), simd::Lane<k>(x.hi)};
  }
  static IMUCONV_KERNEL_INLINE d4x2 Yzx(const d4x2& x) {
    return {simd::Yzx(x.lo), simd::Yzx(x.hi)};
  }
  static IMUCONV_KERNEL_INLINE d4x2 ShiftDown(const d4x2& x) { return {x.hi, d4{}}; }
  static IMUCONV_KERNEL_INLINE d4x2 Los(const d4x2& a, const d4x2& b) { return {a.lo, b.lo}; }
  static IMUCONV_KERNEL_INLINE d4x2 DupHi(const d4x2& a) { return {a.hi, a.hi}; }
};

#if IMUCONV_KERNEL_NARROW
/// Two 4-lane columns on a 128-bit target, by rows: r[k] = (row k of the first, row k of
/// the second). A d4x2 there is four registers, one of them padding; this is three, and
/// the per-half lane broadcasts and rotations (Lane, Yzx) are a choice of register instead
/// of a shuffle. The lanes' arithmetic is the same, operation by operation, as d4x2's.
struct d3x2 {
  d2 r[3];
};
IMUCONV_KERNEL_INLINE d3x2 operator+(const d3x2& a, const d3x2& b) {
  return {{a.r[0] + b.r[0], a.r[1] + b.r[1], a.r[2] + b.r[2]}};
}
IMUCONV_KERNEL_INLINE d3x2 operator-(const d3x2& a, const d3x2& b) {
  return {{a.r[0] - b.r[0], a.r[1] - b.r[1], a.r[2] - b.r[2]}};
}
IMUCONV_KERNEL_INLINE d3x2 operator*(const d3x2& a, const d3x2& b) {
  return {{a.r[0] * b.r[0], a.r[1] * b.r[1], a.r[2] * b.r[2]}};
}
IMUCONV_KERNEL_INLINE d3x2 operator-(const d3x2& a) { return {{-a.r[0], -a.r[1], -a.r[2]}}; }
/// The column of the first block (Lo) and of the second (Hi), lane 3 zero.
IMUCONV_KERNEL_INLINE d4 Lo(const d3x2& x) {
  return {__builtin_shufflevector(x.r[0], x.r[1], 0, 2),
          __builtin_shufflevector(x.r[2], d2{}, 0, 2)};
}
IMUCONV_KERNEL_INLINE d4 Hi(const d3x2& x) {
  return {__builtin_shufflevector(x.r[0], x.r[1], 1, 3),
          __builtin_shufflevector(x.r[2], d2{}, 1, 2)};
}
template <>
struct PairOps<d3x2> {
  static IMUCONV_KERNEL_INLINE d3x2 Cat(const d4& a, const d4& b) {
    return {{__builtin_shufflevector(a.lo, b.lo, 0, 2), __builtin_shufflevector(a.lo, b.lo, 1, 3),
             __builtin_shufflevector(a.hi, b.hi, 0, 2)}};
  }
  static IMUCONV_KERNEL_INLINE d3x2 Splat(double x) {
    const d2 v = {x, x};
    return {{v, v, v}};
  }
  template <int k>
  static IMUCONV_KERNEL_INLINE d3x2 Lane(const d3x2& x) {
    return {{x.r[k], x.r[k], x.r[k]}};
  }
  static IMUCONV_KERNEL_INLINE d3x2 Yzx(const d3x2& x) { return {{x.r[1], x.r[2], x.r[0]}}; }
  static IMUCONV_KERNEL_INLINE d3x2 ShiftDown(const d3x2& x) {
    return {{__builtin_shufflevector(x.r[0], d2{}, 1, 2),
             __builtin_shufflevector(x.r[1], d2{}, 1, 2),
             __builtin_shufflevector(x.r[2], d2{}, 1, 2)}};
  }
  static IMUCONV_KERNEL_INLINE d3x2 Los(const d3x2& a, const d3x2& b) {
    return {{__builtin_shufflevector(a.r[0], b.r[0], 0, 2),
             __builtin_shufflevector(a.r[1], b.r[1], 0, 2),
             __builtin_shufflevector(a.r[2], b.r[2], 0, 2)}};
  }
  static IMUCONV_KERNEL_INLINE d3x2 DupHi(const d3x2& a) {
    return {{__builtin_shufflevector(a.r[0], a.r[0], 1, 1),
             __builtin_shufflevector(a.r[1], a.r[1], 1, 1),
             __builtin_shufflevector(a.r[2], a.r[2], 1, 1)}};
  }
};
#endif

/// Two 3x3 blocks side by side: column j is [column j of the first | of the second].
template <class W>
struct BB {
  W c[3];
};

template <class W>
IMUCONV_KERNEL_INLINE B Lo(const BB<W>& x) {
  return {{Lo(x.c[0]), Lo(x.c[1]), Lo(x.c[2])}};
}
template <class W>
IMUCONV_KERNEL_INLINE B Hi(const BB<W>& x) {
  return {{Hi(x.c[0]), Hi(x.c[1]), Hi(x.c[2])}};
}
template <class W>
IMUCONV_KERNEL_INLINE BB<W> Pair(const B& a, const B& b) {
  using O = PairOps<W>;
  return {{O::Cat(a.c[0], b.c[0]), O::Cat(a.c[1], b.c[1]), O::Cat(a.c[2], b.c[2])}};
}
template <class W>
IMUCONV_KERNEL_INLINE BB<W> operator+(const BB<W>& a, const BB<W>& b) {
  return {{a.c[0] + b.c[0], a.c[1] + b.c[1], a.c[2] + b.c[2]}};
}
/// a + s b with s one scalar or [s1 | s2] per half.
template <class W>
IMUCONV_KERNEL_INLINE BB<W> AddScaled(const BB<W>& a, const W& s, const BB<W>& b) {
  return {{a.c[0] + s * b.c[0], a.c[1] + s * b.c[1], a.c[2] + s * b.c[2]}};
}
/// [a1 b^T | a2 b^T] accumulated into acc (b's entries broadcast over both halves).
template <class W>
IMUCONV_KERNEL_INLINE BB<W> MulTAdd(const BB<W>& acc, const BB<W>& a, const B& b) {
  using O = PairOps<W>;
  BB<W> r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = acc.c[j] + a.c[0] * O::Splat(b.c[0][j]) + a.c[1] * O::Splat(b.c[1][j]) +
             a.c[2] * O::Splat(b.c[2][j]);
  return r;
}
template <class W>
IMUCONV_KERNEL_INLINE BB<W> MulT(const BB<W>& a, const B& b) {
  using O = PairOps<W>;
  BB<W> r;
  for (int j = 0; j < 3; ++j)
    r.c[j] =
        a.c[0] * O::Splat(b.c[0][j]) + a.c[1] * O::Splat(b.c[1][j]) + a.c[2] * O::Splat(b.c[2][j]);
  return r;
}
/// [l1 b | l2 b]: the two blocks of l times the same b (b's entries broadcast).
template <class W>
IMUCONV_KERNEL_INLINE BB<W> MulPair(const BB<W>& l, const B& b) {
  using O = PairOps<W>;
  BB<W> r;
  for (int j = 0; j < 3; ++j)
    r.c[j] =
        l.c[0] * O::Splat(b.c[j][0]) + l.c[1] * O::Splat(b.c[j][1]) + l.c[2] * O::Splat(b.c[j][2]);
  return r;
}
/// [m z1 | m z2] for dm = [m | m]: one m times the two blocks of z.
template <class W>
IMUCONV_KERNEL_INLINE BB<W> MulDup(const BB<W>& dm, const BB<W>& z) {
  using O = PairOps<W>;
  BB<W> r;
  for (int j = 0; j < 3; ++j)
    r.c[j] = dm.c[0] * O::template Lane<0>(z.c[j]) + dm.c[1] * O::template Lane<1>(z.c[j]) +
             dm.c[2] * O::template Lane<2>(z.c[j]);
  return r;
}
/// [z1 [b]x | z2 [b]x].
template <class W>
IMUCONV_KERNEL_INLINE BB<W> TimesSkew(const BB<W>& z, const W& b0, const W& b1, const W& b2) {
  return {{b2 * z.c[1] - b1 * z.c[2], b0 * z.c[2] - b2 * z.c[0], b1 * z.c[0] - b0 * z.c[1]}};
}

}  // namespace simd
IMUCONV_KERNEL_END
