# Shared fixtures of the Python suite: the registry (built-in plugins of this build) and the
# ten reference cases with GTSAM's outputs, copied into tests/data/reference, so the suite needs nothing outside the repository.
import json
import os
import pathlib

import numpy as np
import pytest

import imuconv

DATA = pathlib.Path(os.environ.get("IMUCONV_TEST_DATA", pathlib.Path(__file__).resolve().parents[1] / "data"))
EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "data"
EUROC_IMU = EXAMPLES / "V1_01_easy_imu0_slice.csv"
EUROC_GT = EXAMPLES / "V1_01_easy_groundtruth_vicon2gt_slice.csv"
EUROC_NOISE = {"gyro_noise_density": 1.6968e-04, "accel_noise_density": 2.0e-3,
               "gyro_random_walk": 1.9393e-05, "accel_random_walk": 3.0e-3}  # EuRoC's datasheet
CASE_IDS = ["aggressive-0", "aggressive-1", "jitter-0", "jitter-1", "smooth-0", "smooth-1", "smooth-2", "smooth-3",
            "static-0", "white-0"]


@pytest.fixture(scope="session")
def reg():
    return imuconv.Registry()


def load_case(case_id):
    with open(DATA / "reference" / "cases" / f"{case_id}.json") as f:
        case = json.load(f)
    with open(DATA / "reference" / "gtsam" / f"{case_id}.gtsam.json") as f:
        ref = json.load(f)
    return case, ref


def start_state(case):
    s = case["state_s"]
    return imuconv.State(p=s["p"], q_wxyz=s["q_wxyz"], v=s["v"], bg=s["bg"], ba=s["ba"])


def paper_d(reference, estimate):
    """The note's entrywise difference (tests/data/reference/FORMAT.md): |r - e| / |r| where
    |r| > 1e-4, else |r - e|; the max over entries."""
    r = np.asarray(reference, dtype=float)
    e = np.asarray(estimate, dtype=float)
    assert r.shape == e.shape, (r.shape, e.shape)
    big = np.abs(r) > 1e-4
    d = np.where(big, np.abs(r - e) / np.where(big, np.abs(r), 1.0), np.abs(r - e))
    return float(d.max())


def euroc_rows(path):
    """Integer nanosecond stamps (exact) and the other fields of a EuRoC CSV."""
    stamps, rows = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            fields = line.strip().split(",")
            stamps.append(int(fields[0]))
            rows.append([float(x) for x in fields[1:]])
    return np.array(stamps, dtype=np.int64), np.array(rows)


def euroc_slice():
    """The EuRoC slice of examples/data as the module takes it: samples and poses, their times in
    seconds from the IMU file's first sample (the command's origin), made relative in int64 and
    then divided."""
    t_imu, imu = euroc_rows(EUROC_IMU)
    t_gt, gt = euroc_rows(EUROC_GT)
    origin = t_imu[0]
    return (np.column_stack([(t_imu - origin) * 1e-9, imu]),
            np.column_stack([(t_gt - origin) * 1e-9, gt]))
