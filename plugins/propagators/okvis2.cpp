// `okvis2`: OKVIS2's IMU propagation as upstream codes it (okvis_ceres ImuError::propagation,
// ethz-mrl/okvis2): per step the mean of samples k and k+1 held, the rotation by the exact
// exponential, velocity and position by the trapezoid of the rotation at both ends; its
// d end / d start as the transition, and its covariance from its own per-step F_delta, whose
// four blocks F(p, alpha), F(p, bg), F(v, bg) and F(p, ba) hold whole-interval sums
// (the anchors' README, "OKVIS quirk"): the position variance it reports is 1.3 to 9.4 times
// the linearization of its own step on the reference cases (docs/okvis2.md).
// The case's densities are OKVIS's sigma_*_c unchanged (continuous densities in OKVIS too:
// sigma^2 dt per step on alpha and v, sigma^2 dt^3/2 on p, no p-v cross term).
// The kernel is core/include/imuconv/kernels/okvis2.h (okvis2_scheme.h converts); native
// convention `okvis2` ([r, alpha, v, bg, ba], world, left rotation: `left` by another name).
// It agrees with OKVIS's own numbers on the ten reference cases
// (tests/reference/okvis2_plugins_anchor.cpp).
#include "imuconv/kernels/okvis2_scheme.h"
#include "imuconv/plugin/kernel_registration.h"

// Centered cells, continuous densities (kernels/okvis2_scheme.h); no mean-only integration.
IMUCONV_KERNEL_PROPAGATOR(
    "okvis2", "1.0.0",
    "OKVIS2 ImuError::propagation (trapezoid, exact rotation) with its F_delta "
    "covariance as coded (whole-interval blocks); native okvis2",
    imuconv::kernels::Okvis2PropagationScheme<imuconv::kernels::Okvis2Transition::kAsOkvis>)
