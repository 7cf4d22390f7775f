// `okvis2_step_local`: OKVIS2's IMU propagation (the mean, the transition d end / d start and
// the noise per step of `okvis2`, okvis_ceres ImuError::propagation) with the per-step
// transition the scheme implies: the blocks F(p, alpha), F(p, bg), F(v, bg) and F(p, ba) of
// each step built from that step alone, where upstream's F_delta puts whole-interval sums
// (acc_integral, dv_db_g and its `cross`, C_integral) into them. Not OKVIS's output: the
// variant that tells what upstream's blocks do to its covariance (docs/okvis2.md; with it the
// covariance is OpenVINS discrete's to the position noise term, tests/integrators/okvis2.cpp).
// Same densities, same end state and Jacobian as `okvis2`; native convention `okvis2`.
#include "imuconv/kernels/okvis2_scheme.h"
#include "imuconv/plugin/kernel_registration.h"

IMUCONV_KERNEL_PROPAGATOR(
    "okvis2_step_local", "1.0.0",
    "OKVIS2 ImuError::propagation with step-local F_delta blocks (the exact "
    "transition of its step); native okvis2",
    imuconv::kernels::Okvis2PropagationScheme<imuconv::kernels::Okvis2Transition::kOkvisStepLocal>)
