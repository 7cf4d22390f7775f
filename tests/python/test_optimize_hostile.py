# imuconv.optimize refuses what `imuconv optimize` refuses, with its sentence (the checks are in
# the shared solve, apps/optimize/optimize.cpp): a pose sigma whose information overflows the
# cost, and keyframes whose intervals hold no sample strictly inside.
import pathlib

import numpy as np
import pytest

import imuconv

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "data"
NOISE = {"gyro_noise_density": 1.6968e-04, "accel_noise_density": 2.0e-3,
         "gyro_random_walk": 1.9393e-05, "accel_random_walk": 3.0e-3}  # EuRoC's datasheet

pytestmark = pytest.mark.skipif(not hasattr(imuconv, "optimize"), reason="built without Ceres")


def rows(name):
    """Integer nanosecond stamps and the other fields of a EuRoC CSV in examples/data."""
    data = np.loadtxt(EXAMPLES / name, delimiter=",", comments="#", dtype=np.float64)
    stamps = np.loadtxt(EXAMPLES / name, delimiter=",", comments="#", usecols=0, dtype=np.int64)
    return stamps, data[:, 1:]


def slice_arrays():
    t_imu, imu = rows("V1_01_easy_imu0_slice.csv")
    t_gt, gt = rows("V1_01_easy_groundtruth_vicon2gt_slice.csv")
    origin = t_imu[0]
    return (np.column_stack([(t_imu - origin) * 1e-9, imu]),
            np.column_stack([(t_gt - origin) * 1e-9, gt]))


def test_a_pose_sigma_that_overflows_the_cost_is_refused(reg):
    samples, poses = slice_arrays()
    # Before: 1e-300 "converged" on a NaN cost with every covariance None.
    with pytest.raises(imuconv.Error, match="--pose-sigma: .* at least 1e-9"):
        imuconv.optimize(reg, samples, poses, noise=NOISE, keyframe_step=1.0,
                         pose_sigma=(1e-300, 1e-300))


def test_an_interval_between_two_samples_is_named(reg):
    samples, poses = slice_arrays()
    # Before: "residual covariance ... not positive definite (are all four noise densities
    # positive?)".
    with pytest.raises(imuconv.Error, match=r"interval 1 \[0.005, 0.01\] s holds no IMU sample "
                                            "strictly inside it"):
        imuconv.optimize(reg, samples, poses, noise=NOISE, keyframe_step=0.005)
