// Which compiled instance of the kernels (the preintegration kernel, rk4) runs: chosen from
// the CPU once, on first use. CMake says which instances this build has: IMUCONV_KERNELS_SIMD
// (the baseline SIMD instance, GCC or Clang), IMUCONV_KERNELS_X86 (the AVX2 and AVX-512
// instances, x86-64). Anything else, and Isa::kPortable everywhere, runs the portable path
// (portable.h; rk4's default-target code, rk4.cpp).
#include "instances.h"

namespace imuconv::kernels {

bool IsaAvailable(Isa isa) {
  switch (isa) {
    case Isa::kAuto:
    case Isa::kBaseline:
    case Isa::kPortable:
      return true;
#if defined(IMUCONV_KERNELS_X86)
    case Isa::kAvx2:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case Isa::kAvx512:
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
             __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw");
#else
    case Isa::kAvx2:
    case Isa::kAvx512:
      return false;
#endif
  }
  return false;
}

Isa BestIsa() {
  static const Isa best = IsaAvailable(Isa::kAvx512) ? Isa::kAvx512
                          : IsaAvailable(Isa::kAvx2) ? Isa::kAvx2
                                                     : Isa::kBaseline;
  return best;
}

namespace detail {

Isa ResolveIsa(Isa isa) { return isa == Isa::kAuto ? BestIsa() : isa; }

const Instance* SimdInstance(Isa isa) {
  switch (isa) {
#if defined(IMUCONV_KERNELS_X86)
    case Isa::kAvx512:
      return &kAvx512Instance;
    case Isa::kAvx2:
      return &kAvx2Instance;
#endif
#if defined(IMUCONV_KERNELS_SIMD)
    case Isa::kBaseline:
      return &kBaselineInstance;
#endif
    default:
      return nullptr;
  }
}

}  // namespace detail
}  // namespace imuconv::kernels
