// The baseline instance of the preintegration kernel's SIMD recursion: interval.h
// compiled for the target's baseline instruction set (x86-64: SSE2), its helpers in the
// inline namespace detail::baseline.
//
// The 4-lane values passed between the always-inline helpers would change the ABI of any
// function that took them by value out of line; none is (GCC's -Wpsabi note is moot).
#pragma GCC diagnostic ignored "-Wpsabi"

#include "instances.h"
#include "interval.h"

namespace imuconv::kernels::detail {

extern const Instance kBaselineInstance = {&RunManifoldInstance<simd::d4x2>, &RunTangentInstance<simd::d4x2>};

}  // namespace imuconv::kernels::detail
