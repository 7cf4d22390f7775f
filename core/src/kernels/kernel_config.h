// Build configuration shared by the preintegration kernel's internal headers.
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
// interval.h) and not -mavx2 -mfma for the whole file: the helpers are then compiled for
// the baseline and inlined into the wider function, as they always were. Compiled with the
// flags for the whole file, GCC 12 shapes the same source differently and fuses other
// multiply-adds: the bias Jacobian and covariance move by ~1e-12 relative, within every
// test's tolerance but not the bitwise-unchanged outputs this split must keep. A change of
// the numbers that size is a separate, deliberate step.
#pragma once

#ifndef IMUCONV_KERNEL_ISA
#define IMUCONV_KERNEL_ISA generic
#endif

#define IMUCONV_KERNEL_BEGIN           \
  namespace imuconv::kernels::detail { \
  inline namespace IMUCONV_KERNEL_ISA {
#define IMUCONV_KERNEL_END \
  }                        \
  }

// GCC and Clang have the vector extensions the SIMD blocks are written in; any other
// compiler gets the portable Eigen path only (see dispatch.cpp).
#if defined(__GNUC__)
#define IMUCONV_KERNEL_HAS_VECTORS 1
#define IMUCONV_KERNEL_INLINE inline __attribute__((always_inline))
#else
#define IMUCONV_KERNEL_HAS_VECTORS 0
#define IMUCONV_KERNEL_INLINE inline
#endif
