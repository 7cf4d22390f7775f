// `fast_lio2`: FAST-LIO2's IMU forward propagation (ImuProcess driving IKFoM's esekf::predict
// on use-ikfom.hpp's state), as FAST-LIO builds it: the mean of consecutive samples held over
// each step, rot = rot Exp((w - bg) dt) exact, vel += (rot (a - ba) + g) dt and pos += vel dt
// (first order, from the pre-step state), and the covariance P = F P F^T + (dt G) Q (dt G)^T
// with F's rotation block the IDENTITY where the step's transition is Exp(-w dt): IKFoM's
// predict writes that block's half-angle as scalar_type(1/2), an integer division equal to 0
// (IKFoM issue #16). `fast_lio2_exact_rotation` is the same with Exp(-w dt) there.
//
// Noise: the four ImuNoise numbers are continuous densities sigma, mapped as FAST-LIO's code
// needs them: its Q (gyr_cov, acc_cov, b_gyr_cov, b_acc_cov) enters as Q dt^2 per step, so
// Q = sigma^2 f, per-sample variances at the nominal rate f, taken as the window's mean rate
// (knots - 1) / (t_e - t_s): one Q per window, as ImuProcess has one. On regular sampling
// each step then adds sigma^2 dt (the continuous noise's own discretization); on irregular
// sampling sigma^2 dt_k^2 / mean dt, as FAST-LIO does. `fast_lio2_as_configured` takes
// FAST-LIO's own four numbers instead.
//
// Gravity is the one the caller gives, at its own length (the pipeline's `gravity`): FAST-LIO
// itself propagates with its S2 gravity of length 9.809 while it scales the accelerometers to
// 9.81; give gravity [0, 0, -9.809] to get that (docs/fast-lio2.md measures what it does).
//
// Native convention `fast_lio2` ([pos, rot, vel, bg, ba] of IKFoM's 23-dimensional state;
// the extrinsic and S2 gravity blocks are in the kernel, core/include/imuconv/kernels/
// fast_lio2.h). With the file's config numbers (`fast_lio2_as_configured`) it agrees with
// FAST-LIO's own end state, covariance and transition on the ten reference cases to 1e-8
// (tests/reference/fast_lio2_plugins.cpp).
#include "imuconv/kernels/fast_lio2.h"
#include "imuconv/plugin/kernel_registration.h"

IMUCONV_KERNEL_PROPAGATOR(
    "fast_lio2", "1.0.0",
    "FAST-LIO2 ImuProcess + IKFoM predict as built (identity rotation block of F, "
    "scalar_type(1/2) = 0); densities as Q = sigma^2 f; native fast_lio2",
    imuconv::kernels::FastLio2AsBuilt)
