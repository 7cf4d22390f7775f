// Build configuration shared by the internal headers of the kernels compiled per instruction
// set: the preintegration kernel's recursion and rk4's window integration.
//
// Instances. The block recursion is compiled once per instruction set, each in its own
// translation unit (instance_*.cpp). Every inline helper
// those units share would otherwise be one weak symbol compiled several ways, and the
// linker would keep any one copy: an AVX2 copy could then run on a CPU without AVX2. So
// the internal headers put their contents in an inline namespace named after the unit's
// instruction set (IMUCONV_KERNEL_ISA, set per file by CMake; "generic" elsewhere), which
// gives each instance its own symbols while the code still says kernels::detail::Foo.
//
// Why a target attribute on each instance's interval functions (IMUCONV_KERNEL_TARGET,
// interval.h) and not -mavx2 -mfma for the whole file:
// - Safety. The inline namespace covers imuconv's own helpers, not Eigen's or core's inline
//   functions, which every unit shares as weak symbols. Built with the flags for the whole
//   file, any of those the compiler emits out of line is an AVX2 copy, and the linker keeps
//   one copy for the whole library: a CPU without AVX2 would then die of SIGILL outside the
//   kernel. GCC 12 emits 616 such symbols from instance_avx2.cpp at -O0 (none at -O1 and
//   above, by inlining luck, not by rule). With the attribute only the interval functions
//   are wide; whatever they do not inline stays baseline code.
// - Numbers. With the flags GCC 12 also fuses other multiply-adds: the bias Jacobian and
//   covariance move by ~1e-12 relative, within every test's tolerance but a change of the
//   outputs for no gain.
#pragma once

#ifndef IMUCONV_KERNEL_ISA
#define IMUCONV_KERNEL_ISA generic
#endif

// IMUCONV_KERNEL_NARROW (set by instance_baseline.cpp): the target's vectors are 128-bit
// (SSE2, NEON), so simd::d4 is built from two native 2-lane halves (simd_block3.h).
#ifndef IMUCONV_KERNEL_NARROW
#define IMUCONV_KERNEL_NARROW 0
#endif

#define IMUCONV_KERNEL_BEGIN           \
  namespace imuconv::kernels::detail { \
  inline namespace IMUCONV_KERNEL_ISA {
#define IMUCONV_KERNEL_END \
  }                        \
  }

// GCC and Clang have the vector extensions the SIMD blocks are written in; any other
// compiler gets the portable Eigen path only (see dispatch.cpp).
// rk4's window integration (rk4_window.h) is compiled per instance through one entry,
// Rk4Window, which IMUCONV_RK4_ENTRY marks: the instance's target (IMUCONV_RK4_TARGET, set by
// the unit before it includes rk4_window.h; none for the default target), `flatten` so the
// whole step is compiled for that target, and no fused multiply-adds (rk4_window.h,
// "Instances", says why). GCC takes fp-contract=off per function, so it compiles the AVX2 and
// AVX-512 instances of rk4 (IMUCONV_RK4_PER_INSTANCE). Clang decides contraction per statement
// in its front end, before inlining, and has no per-function switch for the code it inlines
// (Eigen's), so it compiles rk4 once, for the default target (rk4.cpp), which every instance
// then runs.
#if defined(__GNUC__) && !defined(__clang__)
#define IMUCONV_RK4_PER_INSTANCE 1
#define IMUCONV_RK4_CODEGEN __attribute__((optimize("fp-contract=off"), flatten, noinline))
#else
#define IMUCONV_RK4_PER_INSTANCE 0
#define IMUCONV_RK4_CODEGEN
#endif

#if defined(__GNUC__)
#define IMUCONV_KERNEL_HAS_VECTORS 1
#define IMUCONV_KERNEL_INLINE inline __attribute__((always_inline))
#else
#define IMUCONV_KERNEL_HAS_VECTORS 0
#define IMUCONV_KERNEL_INLINE inline
#endif
