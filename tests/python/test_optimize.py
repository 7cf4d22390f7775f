# imuconv.optimize on arrays against `imuconv optimize --json` on the same EuRoC slice files: the
# module and the command are one computation, so their keyframes agree but for the rounding of the
# times (the files' integer nanoseconds, made relative here in int64 and then divided).
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import imuconv

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "data"
IMU = EXAMPLES / "V1_01_easy_imu0_slice.csv"
GT = EXAMPLES / "V1_01_easy_groundtruth_vicon2gt_slice.csv"
NOISE = {"gyro_noise_density": 1.6968e-04, "accel_noise_density": 2.0e-3,
         "gyro_random_walk": 1.9393e-05, "accel_random_walk": 3.0e-3}  # EuRoC's datasheet

pytestmark = pytest.mark.skipif(not hasattr(imuconv, "optimize"), reason="built without Ceres")


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


def slice_arrays():
    t_imu, imu = euroc_rows(IMU)
    t_gt, gt = euroc_rows(GT)
    origin = t_imu[0]  # the command's origin: the IMU file's first sample
    samples = np.column_stack([(t_imu - origin) * 1e-9, imu])
    poses = np.column_stack([(t_gt - origin) * 1e-9, gt])
    return samples, poses


def test_optimize_matches_the_command(reg, tmp_path):
    samples, poses = slice_arrays()
    out = imuconv.optimize(reg, samples, poses, noise=NOISE, keyframe_step=2.0)
    assert out["converged"]
    k = out["t"].shape[0]
    assert k >= 2
    for key, width in (("p", 3), ("v", 3), ("bg", 3), ("ba", 3), ("q_wxyz", 4)):
        assert out[key].shape == (k, width), key
    assert out["cov"].shape == (k, 15, 15)
    assert len(out["blocks"]) == 5

    noise_file = tmp_path / "noise.json"
    noise_file.write_text(json.dumps({"noise": NOISE}))
    binary = os.environ.get("IMUCONV_BINARY")
    if not binary:
        pytest.skip("IMUCONV_BINARY not set (ctest sets it)")
    cli = json.loads(subprocess.run(
        [binary, "optimize", "--imu", str(IMU), "--poses", str(GT), "--noise", str(noise_file),
         "--keyframe-step", "2.0", "--json"], check=True, capture_output=True, text=True).stdout)
    kfs = cli["keyframes"]
    assert len(kfs) == k
    # The times differ by the rounding of (ns - origin) * 1e-9 against the reader's exact
    # difference, ~1e-16 s relative; through the solve that moves the states by far less than
    # 1e-8, and a different computation (another default, another chart) by 1e-4 and more.
    for i, kf in enumerate(kfs):
        assert abs(kf["t"] - out["t"][i]) < 1e-9
        for key in ("p", "v", "bg", "ba", "q_wxyz"):
            np.testing.assert_allclose(out[key][i], kf[key], rtol=0, atol=1e-8, err_msg=key)
        # The covariances come from the same factorisation; the time rounding moves them by
        # ~1e-12 relative, another noise or chart by per cent. atol: 1e-14 is far below the
        # smallest variance (of bg, ~1e-8) and absorbs rounding in entries that are ~0.
        np.testing.assert_allclose(out["cov"][i], np.array(kf["cov"]), rtol=1e-6, atol=1e-14)


def test_optimize_refuses_bad_poses(reg):
    samples, poses = slice_arrays()
    with pytest.raises(ValueError, match="poses: expected shape"):
        imuconv.optimize(reg, samples, poses[:, :5], noise=NOISE, keyframe_step=2.0)
    bad = poses.copy()
    bad[3, 0] = bad[2, 0]
    with pytest.raises(ValueError, match="row 3"):
        imuconv.optimize(reg, samples, bad, noise=NOISE, keyframe_step=2.0)
    with pytest.raises(imuconv.Error, match="keyframe-step"):
        imuconv.optimize(reg, samples, poses, noise=NOISE, keyframe_step=1000.0)
