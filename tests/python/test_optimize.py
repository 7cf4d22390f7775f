# imuconv.optimize on arrays against `imuconv optimize --json` on the same EuRoC slice files: the
# module and the command are one computation, so their keyframes agree but for the rounding of the
# times (the files' integer nanoseconds, made relative in int64 and then divided: conftest.euroc_slice).
import json
import os
import subprocess
import warnings

import numpy as np
import pytest

import imuconv
from conftest import EUROC_GT, EUROC_IMU, EUROC_NOISE, euroc_slice

pytestmark = pytest.mark.skipif(not hasattr(imuconv, "optimize"), reason="built without Ceres")


def test_optimize_matches_the_command(reg, tmp_path):
    samples, poses = euroc_slice()
    out = imuconv.optimize(reg, samples, poses, noise=EUROC_NOISE, keyframe_step=2.0)
    assert out["converged"]
    k = out["t"].shape[0]
    assert k >= 2
    for key, width in (("p", 3), ("v", 3), ("bg", 3), ("ba", 3), ("q_wxyz", 4)):
        assert out[key].shape == (k, width), key
    assert out["cov"].shape == (k, 15, 15)
    assert len(out["blocks"]) == 5

    noise_file = tmp_path / "noise.json"
    noise_file.write_text(json.dumps({"noise": EUROC_NOISE}))
    binary = os.environ.get("IMUCONV_BINARY")
    if not binary:
        pytest.skip("IMUCONV_BINARY not set (ctest sets it)")
    cli = json.loads(subprocess.run(
        [binary, "optimize", "--imu", str(EUROC_IMU), "--poses", str(EUROC_GT), "--noise", str(noise_file),
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
    samples, poses = euroc_slice()
    with pytest.raises(ValueError, match="poses: expected shape"):
        imuconv.optimize(reg, samples, poses[:, :5], noise=EUROC_NOISE, keyframe_step=2.0)
    bad = poses.copy()
    bad[3, 0] = bad[2, 0]
    with pytest.raises(ValueError, match="row 3"):
        imuconv.optimize(reg, samples, bad, noise=EUROC_NOISE, keyframe_step=2.0)
    with pytest.raises(imuconv.Error, match="keyframe-step"):
        imuconv.optimize(reg, samples, poses, noise=EUROC_NOISE, keyframe_step=1000.0)


def test_optimize_warns_when_the_poses_disagree_with_the_gyro(reg):
    # The slice's poses with each quaternion written x,y,z,w in the w,x,y,z columns (still unit):
    # a UserWarning naming the poses, and the solve still runs; the true poses give none.
    samples, poses = euroc_slice()
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        imuconv.optimize(reg, samples, poses, noise=EUROC_NOISE, keyframe_step=2.0)
    reordered = poses.copy()
    reordered[:, 4:8] = poses[:, [5, 6, 7, 4]]
    with pytest.warns(UserWarning, match=r"imuconv: poses: the poses' rotations disagree with the gyro"):
        out = imuconv.optimize(reg, samples, reordered, noise=EUROC_NOISE, keyframe_step=2.0)
    assert out["t"].shape[0] >= 2
