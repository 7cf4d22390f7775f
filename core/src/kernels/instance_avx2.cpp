// The avx2 instance of the kernels: the preintegration kernel's SIMD recursion (interval.h
// with its interval functions compiled for AVX2, FMA, see kernel_config.h) and, with GCC,
// rk4's window integration (rk4_window.h, for AVX2, FMA without fused multiply-adds), their
// helpers in the inline namespace detail::avx2. dispatch.cpp runs it only on a CPU that has
// them.
//
// The 4-lane values passed between the always-inline helpers would change the ABI of any
// function that took them by value out of line; none is (GCC's -Wpsabi note is moot).
#pragma GCC diagnostic ignored "-Wpsabi"

#define IMUCONV_KERNEL_TARGET __attribute__((target("avx2,fma")))
#include "instance_x86.h"

namespace imuconv::kernels::detail {

extern const Instance kAvx2Instance = X86Instance<simd::d4x2>();

}  // namespace imuconv::kernels::detail
