// `fast_lio2_as_configured`: `fast_lio2` (FAST-LIO2's forward propagation as built, identity
// rotation block of F included; native convention `fast_lio2`) with the four noise numbers
// used as FAST-LIO uses its configuration's mapping/gyr_cov, acc_cov, b_gyr_cov and
// b_acc_cov (laserMapping.cpp passes them to ImuProcess's set_*_cov; UndistortPcl puts them
// on the diagonal of Q, and predict adds Q dt^2 per step): gyro_noise_density is gyr_cov,
// accel_noise_density acc_cov, gyro_random_walk b_gyr_cov and accel_random_walk b_acc_cov,
// each a per-sample VARIANCE, used as given (not squared, not scaled by any rate). Give it
// the four values of a FAST-LIO configuration file to get that run's covariance. They are
// the densities' sigma^2 f (what `fast_lio2` forms) only when they were chosen so.
#include "imuconv/kernels/fast_lio2.h"
#include "imuconv/plugin/kernel_registration.h"

IMUCONV_KERNEL_PROPAGATOR(
    "fast_lio2_as_configured", "1.0.0",
    "FAST-LIO2 propagation as built; noise numbers used as its gyr_cov, acc_cov, "
    "b_gyr_cov, b_acc_cov (per-sample variances)",
    imuconv::kernels::FastLio2AsConfigured)
