// The compiled instances of the kernels, one per instruction set (instance_*.cpp, each
// built with its own compiler flags): the preintegration kernel's SIMD recursion and rk4's
// window integration, as dispatch.cpp and the entry points (preintegration.cpp, rk4.cpp) see
// them: plain functions over Eigen types, so no vector type crosses a translation unit.
#pragma once

#include "imuconv/kernels/common.h"  // Outputs
#include "imuconv/kernels/preintegration.h"
#include "imuconv/propagator.h"

namespace imuconv::kernels::detail {

/// One instance. Each function runs its scheme over the window without checking the
/// input, and returns the increment, its bias Jacobian (9x6, columns [ba, bg]) and, when
/// `cov` is not null, its 15x15 covariance [theta, p, v, ba, bg], all in the kernel's own
/// chart: start-frame (Exp(phi) dR, dp + e_p, dv + e_v) for manifold, additive xi for
/// tangent.
struct Instance {
  void (*manifold)(const PreintegrationInput& in, Hold hold, ManifoldIncrement& inc,
                   Mat96& J_inc_bias, Mat15* cov);
  void (*tangent)(const PreintegrationInput& in, TangentIncrement& inc, Mat96& J_inc_bias,
                  Mat15* cov);
  /// rk4 over the window of `in` with `substeps` steps per knot interval, the outputs asked
  /// (IntegrateRk4Window, kernels/rk4.h), without checking the input.
  void (*rk4)(const PropagationInput& in, Outputs outputs, int substeps, PropagationResult& out);
};

// Defined where CMake compiles them (IMUCONV_KERNELS_SIMD, IMUCONV_KERNELS_X86).
extern const Instance kBaselineInstance;  ///< x86-64 / the target's baseline
extern const Instance kAvx2Instance;      ///< AVX2 + FMA
extern const Instance kAvx512Instance;    ///< AVX-512 F, VL, DQ, BW

/// rk4 compiled for the default target (rk4.cpp): the portable path's rk4, and the baseline
/// instance's (and, with Clang, every instance's; kernel_config.h).
void Rk4DefaultTarget(const PropagationInput& in, Outputs outputs, int substeps,
                      PropagationResult& out);

/// The SIMD instance for a resolved `isa`, or null where the portable path is to run
/// (Isa::kPortable, and every isa on a build without SIMD instances, i.e. a compiler without
/// vector extensions).
const Instance* SimdInstance(Isa isa);

/// `isa` with kAuto replaced by BestIsa().
Isa ResolveIsa(Isa isa);

}  // namespace imuconv::kernels::detail
