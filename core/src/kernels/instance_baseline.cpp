// The baseline instance of the preintegration kernel's SIMD recursion: interval.h
// compiled for the target's baseline instruction set (x86-64: SSE2), its helpers in the
// inline namespace detail::baseline. dispatch.cpp runs it where AVX2 is missing and on
// every non-x86 build with GCC or Clang.
//
// The 4-lane values passed between the always-inline helpers would change the ABI of any
// function that took them by value out of line; none is (GCC's -Wpsabi note is moot).
#pragma GCC diagnostic ignored "-Wpsabi"

// 128-bit vectors on every target this unit is built for (x86-64: SSE2; aarch64: NEON):
// simd::d4 as two native 2-lane halves (simd_block3.h).
#define IMUCONV_KERNEL_NARROW 1
#include "instances.h"
#include "interval.h"

namespace imuconv::kernels::detail {

// rk4 at the baseline target is the default-target compilation (rk4.cpp explains why it is
// not compiled a second time here).
extern const Instance kBaselineInstance = {&RunManifoldInstance<simd::d3x2>,
                                           &RunTangentInstance<simd::d3x2>, &Rk4DefaultTarget};

}  // namespace imuconv::kernels::detail
