// The compiled instances of the preintegration kernel's SIMD recursion, one per
// instruction set (instance_*.cpp, each built with its own compiler flags), as dispatch.cpp
// and the entry points (preintegration.cpp) see them: plain functions over Eigen types, so
// no vector type crosses a translation unit.
#pragma once

#include "imuconv/kernels/preintegration.h"

namespace imuconv::kernels::detail {

/// One instance. Each function runs its scheme over the window without checking the
/// input, and returns the increment, its bias Jacobian (9x6, columns [ba, bg]) and, when
/// `cov` is not null, its 15x15 covariance [theta, p, v, ba, bg], all in the kernel's own
/// chart: start-frame (Exp(phi) dR, dp + e_p, dv + e_v) for manifold, additive xi for
/// tangent.
struct Instance {
  void (*manifold)(const PreintegrationInput& in, Hold hold, ManifoldIncrement& inc, Mat96& J_inc_bias, Mat15* cov);
  void (*tangent)(const PreintegrationInput& in, TangentIncrement& inc, Mat96& J_inc_bias, Mat15* cov);
};

// Defined where CMake compiles them (IMUCONV_KERNELS_SIMD, IMUCONV_KERNELS_X86).
extern const Instance kBaselineInstance;  ///< x86-64 / the target's baseline
extern const Instance kAvx2Instance;      ///< AVX2 + FMA
extern const Instance kAvx512Instance;    ///< AVX-512 F, VL, DQ, BW

/// The SIMD instance for a resolved `isa`, or null where the portable path is to run (every
/// isa on a build without SIMD instances, i.e. a compiler without vector extensions).
const Instance* SimdInstance(Isa isa);

/// `isa` with kAuto replaced by BestIsa().
Isa ResolveIsa(Isa isa);

}  // namespace imuconv::kernels::detail
