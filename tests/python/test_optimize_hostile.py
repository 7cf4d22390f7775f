# imuconv.optimize refuses what `imuconv optimize` refuses, with its sentence (the checks are in
# the shared solve, apps/optimize/optimize.cpp): a pose sigma whose information overflows the
# cost, and keyframes whose intervals hold no sample strictly inside.
import pytest

import imuconv
from conftest import EUROC_NOISE, euroc_slice

pytestmark = pytest.mark.skipif(not hasattr(imuconv, "optimize"), reason="built without Ceres")


def test_a_pose_sigma_that_overflows_the_cost_is_refused(reg):
    samples, poses = euroc_slice()
    # Before: 1e-300 "converged" on a NaN cost with every covariance None.
    with pytest.raises(imuconv.Error, match="--pose-sigma: .* at least 1e-9"):
        imuconv.optimize(reg, samples, poses, noise=EUROC_NOISE, keyframe_step=1.0,
                         pose_sigma=(1e-300, 1e-300))


def test_an_interval_between_two_samples_is_named(reg):
    samples, poses = euroc_slice()
    # Before: "residual covariance ... not positive definite (are all four noise densities
    # positive?)".
    with pytest.raises(imuconv.Error, match=r"interval 1 \[0.005, 0.01\] s holds no IMU sample "
                                            "strictly inside it"):
        imuconv.optimize(reg, samples, poses, noise=EUROC_NOISE, keyframe_step=0.005)
