// `fast_lio2_exact_rotation`: `fast_lio2` (FAST-LIO2's forward propagation, the densities
// mapped to its per-sample variances at the window's mean rate, native convention
// `fast_lio2`) with the rotation block of each step's transition Exp(-w dt), the half-angle
// IKFoM's predict meant where it wrote scalar_type(1/2) (an integer division: 0, so the
// identity). That block is the derivative of the step rot Exp(w dt) with respect to the
// start's right perturbation: R^ Exp(d) Exp(w dt) = R^ Exp(w dt) Exp(Exp(-w dt) d). The mean
// is FAST-LIO's own (the state update uses the half-angle correctly); only the covariance and
// the transition differ. The variant exists to measure what the quirk does to a user
// (docs/fast-lio2.md); FAST-LIO's own numbers are `fast_lio2`'s.
#include "imuconv/kernels/fast_lio2.h"
#include "imuconv/plugin/kernel_registration.h"

IMUCONV_KERNEL_PROPAGATOR(
    "fast_lio2_exact_rotation", "1.0.0",
    "FAST-LIO2 propagation with the rotation block of F Exp(-w dt), the half-angle "
    "IKFoM meant; densities as Q = sigma^2 f; native fast_lio2",
    imuconv::kernels::FastLio2ExactRotation)
