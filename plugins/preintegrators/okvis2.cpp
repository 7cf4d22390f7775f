// `okvis2`: OKVIS2's preintegration as its ImuError holds it (okvis_ceres
// ImuError::redoPreintegration, ethz-mrl/okvis2): Delta_q, acc_doubleintegral and
// acc_integral (the trapezoid of `okvis2`'s propagation), P_delta from upstream's per-step
// F_delta (its whole-interval blocks kept: position variance 1.3 to 9.4 times its step's
// linearization on the reference cases, docs/okvis2.md), and the bias Jacobians of
// ImuError's first-order correction, dalpha_db_g (with each step's right Jacobian), dv_db_g,
// dp_db_g, -C_doubleintegral, -C_integral.
// The case's densities are OKVIS's sigma_*_c unchanged (OKVIS reads them as continuous
// densities: sigma^2 dt per step; no `_as_configured` form is needed).
// Covariance and bias Jacobian in the `okvis2` increment convention ([p, alpha, v, bg, ba],
// frame S0, Delta_C = Exp(dalpha) Delta_C^). The kernel is
// core/include/imuconv/kernels/okvis2.h (okvis2_scheme.h converts); it agrees with OKVIS's own
// numbers on the ten reference cases (tests/reference/okvis2_plugins_anchor.cpp).
#include "imuconv/kernels/okvis2_scheme.h"
#include "imuconv/plugin/kernel_registration.h"

IMUCONV_KERNEL_PREINTEGRATOR(
    "okvis2", "1.0.0",
    "OKVIS2 ImuError::redoPreintegration (trapezoid), P_delta from its F_delta as "
    "coded; okvis2 chart",
    imuconv::kernels::Okvis2PreintegrationScheme<imuconv::kernels::Okvis2Transition::kAsOkvis>)
