// The avx512 instance of the kernels: the preintegration kernel's SIMD recursion (interval.h
// with its interval functions compiled for AVX512F, AVX512VL, AVX512DQ, AVX512BW, AVX2, FMA,
// see kernel_config.h) and, with GCC, rk4's window integration (rk4_window.h, for the same
// instruction sets without fused multiply-adds), their helpers in the inline namespace
// detail::avx512. dispatch.cpp runs it only on a CPU that has them.
//
// The 4-lane values passed between the always-inline helpers would change the ABI of any
// function that took them by value out of line; none is (GCC's -Wpsabi note is moot).
#pragma GCC diagnostic ignored "-Wpsabi"

#define IMUCONV_KERNEL_TARGET __attribute__((target("avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")))
#include "instance_x86.h"

namespace imuconv::kernels::detail {

extern const Instance kAvx512Instance = X86Instance<simd::d8>();

}  // namespace imuconv::kernels::detail
