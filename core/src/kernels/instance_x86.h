// What the two x86 instances (instance_avx2.cpp, instance_avx512.cpp) share: the
// preintegration kernel's SIMD recursion (interval.h) and, with GCC, rk4's window integration
// (rk4_window.h, without fused multiply-adds), both compiled for the including unit's
// instruction sets. The unit defines IMUCONV_KERNEL_TARGET before it includes this header and
// defines its Instance as X86Instance<its lane type>(); no other unit includes it.
#pragma once

#include "instances.h"
#include "interval.h"
#if IMUCONV_RK4_PER_INSTANCE
#define IMUCONV_RK4_TARGET IMUCONV_KERNEL_TARGET
#include "rk4_window.h"
#endif

IMUCONV_KERNEL_BEGIN

/// The instance whose recursions run on lanes W, and whose rk4 is compiled for this unit's
/// target where the compiler can keep it unfused (GCC), else the default target's (Clang
/// compiles rk4 once; kernel_config.h says why).
template <class W>
constexpr Instance X86Instance() {
#if IMUCONV_RK4_PER_INSTANCE
  constexpr auto rk4 = &Rk4Window;
#else
  constexpr auto rk4 = &Rk4DefaultTarget;
#endif
  return {&RunManifoldInstance<W>, &RunTangentInstance<W>, rk4};
}

IMUCONV_KERNEL_END
