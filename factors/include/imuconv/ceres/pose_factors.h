// Costs on one state, so that a problem is complete without vision: a prior in any state
// convention and a pose measurement in SO(3) x R^3.
#pragma once

#include <ceres/cost_function.h>

#include <string_view>

#include "imuconv/ceres/export.h"
#include "imuconv/registry.h"
#include "imuconv/types.h"

namespace imuconv::ceres_factors {

/// A prior on one state: r = S local_C(x_prior, x), S^T S = cov^{-1} (S = C^{-1}, cov = C C^T),
/// with cov (15x15) in convention C's chart and block order. One block (16). Throws
/// imuconv::Error for an unknown convention or a cov that is not symmetric positive definite.
/// `reg` must outlive the cost.
IMUCONV_CERES_API ::ceres::CostFunction* MakeStatePrior(const Registry& reg,
                                                        std::string_view convention,
                                                        const ImuState& x_prior, const Mat15& cov);

/// A pose measurement of one state: r = [Log(R_meas^T R) / sigma_rot; (p - p_meas) / sigma_pos]
/// (6 residuals: theta first, then p). One block (16). Throws imuconv::Error for a sigma that is
/// not positive and finite, or an R_meas that is not a rotation.
IMUCONV_CERES_API ::ceres::CostFunction* MakePoseMeasurement(const Mat3& R_meas, const Vec3& p_meas,
                                                             double sigma_pos_m,
                                                             double sigma_rot_rad);

}  // namespace imuconv::ceres_factors
