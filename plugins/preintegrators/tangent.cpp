// `tangent`: GTSAM's TangentPreintegration scheme with the covariance of
// PreintegratedCombinedMeasurements (15x15, [theta, p, v, ba, bg]) and the bias Jacobian,
// both additive on the tangent 9-vector [theta, p, v] with dR = Exp(theta) (paper,
// "GTSAM Peculiarities": the tangent covariance follows the j perturbation).
// The numerics live in imuconv/kernels/preintegration.h (compiled into imuconv_core).
#include "imuconv/kernels/gtsam_scheme.h"
#include "imuconv/plugin/kernel_registration.h"

IMUCONV_KERNEL_PREINTEGRATOR(
    "tangent", "1.0.0", "GTSAM TangentPreintegration + combined 15x15 covariance, zero-order hold",
    imuconv::kernels::GtsamScheme<imuconv::kernels::GtsamPreintegration::kTangent>)
