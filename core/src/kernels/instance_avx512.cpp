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
#include "instances.h"
#include "interval.h"
#if IMUCONV_RK4_PER_INSTANCE
#define IMUCONV_RK4_TARGET IMUCONV_KERNEL_TARGET
#include "rk4_window.h"
#endif

namespace imuconv::kernels::detail {

extern const Instance kAvx512Instance = {&RunManifoldInstance<simd::d8>,
                                         &RunTangentInstance<simd::d8>,
#if IMUCONV_RK4_PER_INSTANCE
                                         &Rk4Window};
#else
                                         &Rk4DefaultTarget};  // kernel_config.h: Clang compiles rk4
                                                              // once
#endif

}  // namespace imuconv::kernels::detail
