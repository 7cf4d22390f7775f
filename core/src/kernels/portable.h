// The portable path of the preintegration kernel: the same recursion as the SIMD
// instances, on Eigen 3x3 blocks, for any compiler and CPU. It runs only where the compiler
// has no GCC/Clang vector extensions (dispatch.cpp); tests/preintegrators/portable_path.cpp
// compares it with the baseline instance.
#pragma once

#include "imuconv/kernels/preintegration.h"

namespace imuconv::kernels::detail {

/// Manifold scheme: bias Jacobian in the chart (dR Exp(dtheta), dp + ddp, dv + ddv),
/// covariance in GTSAM's NavState chart (left untouched without `covariance`).
void ManifoldPortable(const PreintegrationInput& in, bool covariance, ManifoldIncrement& inc,
                      Mat96& J_inc_bias, Mat15& cov);
/// Tangent scheme: bias Jacobian and covariance additive on xi.
void TangentPortable(const PreintegrationInput& in, bool covariance, TangentIncrement& inc,
                     Mat96& J_inc_bias, Mat15& cov);
/// Manifold scheme in its start-frame chart with either hold (IntegrateManifoldStartFrame
/// where there is no SIMD instance).
void ManifoldStartFramePortable(const PreintegrationInput& in, Hold hold, bool covariance,
                                StartFrameManifold& out);

}  // namespace imuconv::kernels::detail
