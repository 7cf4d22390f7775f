// `manifold`: GTSAM's ManifoldPreintegration scheme with the covariance of
// PreintegratedCombinedMeasurements (15x15, [theta, p, v, ba, bg], NavState chart of the
// increment, paper eq. residual-error) and the bias Jacobian in dR Exp(dtheta), additive
// dp, dv (paper, "GTSAM Peculiarities", eq. preint-error-dr..db).
// The numerics live in imuconv/kernels/preintegration.h (compiled into imuconv_core).
#include "imuconv/kernels/gtsam_scheme.h"
#include "imuconv/plugin/kernel_registration.h"

IMUCONV_KERNEL_PREINTEGRATOR(
    "manifold", "1.0.0",
    "GTSAM ManifoldPreintegration + combined 15x15 covariance, zero-order hold",
    imuconv::kernels::GtsamScheme<imuconv::kernels::GtsamPreintegration::kManifold>)
