// One keyframe's Ceres parameter block, and the ambient Jacobians of the reference state chart
// `left` (reference_charts.h) with respect to it. Every cost of imuconv::ceres differentiates
// with respect to the block through these (factors/README.md says why).
#pragma once

#include <Eigen/Core>

#include "imuconv/ceres/export.h"
#include "imuconv/types.h"

namespace imuconv::ceres_factors {

/// One keyframe's parameter block: [p(3), q_wxyz(4), v(3), bg(3), ba(3)] (q: R = R_ws as a unit
/// quaternion, w first like the CLI's q_wxyz columns).
inline constexpr int kStateBlockSize = 16;
/// The dimension of every state convention's tangent space.
inline constexpr int kStateTangentSize = 15;

/// Offsets of the parts of a state block.
namespace block_idx {
inline constexpr int p = 0, q = 3, v = 7, bg = 10, ba = 13;
}

/// Writes x into block (16 doubles); the quaternion with w >= 0.
IMUCONV_CERES_API void ToStateBlock(const ImuState& x, double* block);
/// The state of a block; its quaternion is normalized first (Ceres's steps stay on the
/// manifold, a user's initial values may not).
IMUCONV_CERES_API ImuState FromStateBlock(const double* block);

/// M_left(x) (15x16): d local_left(x, y) / d y's ambient coordinates at y = x, analytic.
IMUCONV_CERES_API Eigen::Matrix<double, 15, 16, Eigen::RowMajor> LeftMinusJacobian(
    const double* block);
/// P_left(x) (16x15): d retract_left(x, d) / d d at d = 0 in ambient coordinates, analytic.
IMUCONV_CERES_API Eigen::Matrix<double, 16, 15, Eigen::RowMajor> LeftPlusJacobian(
    const double* block);

/// H M_left(x) for a Jacobian H with respect to the left chart (rows x 15): the ambient
/// Jacobian (rows x 16, row-major) Ceres asks a cost for, without the 15x16 product (M_left is
/// the identity but for its 3x4 quaternion block).
IMUCONV_CERES_API void LeftToAmbient(const Eigen::Ref<const Eigen::MatrixXd>& H,
                                     const double* block, double* ambient);

}  // namespace imuconv::ceres_factors
