# The pipeline's checks of IMU samples, noise and results, made by the Python module too (issue
# 22): one set of checks in the library (imuconv/pipeline/sample_checks.h), the same sentences
# as `imuconv run` gives; and the timing rules of the pipeline reached through imuconv.run and
# imuconv.check (intervals holding no sample, a knot within a nanosecond of a sample).
import json

import numpy as np
import pytest

import imuconv

NOISE = {"gyro_noise_density": 1.7e-4, "accel_noise_density": 2.0e-3, "gyro_random_walk": 1.9e-5,
         "accel_random_walk": 3.0e-3}
ZERO = np.zeros(3)


def samples(n=201, rate=200.0, t0=0.0):
    """n samples at `rate` Hz from t0 (s): a slow turn and a gentle push, gravity on z. Times
    rounded to 1e-12 s, so that k / rate is written as the decimal it means (0.3, not
    0.30000000000000004)."""
    t = np.round(t0 + np.arange(n) / rate, 12)
    s = np.zeros((n, 7))
    s[:, 0] = t
    s[:, 1:4] = [0.1, -0.2, 0.3]
    s[:, 4] = 0.2 * np.sin(t)
    s[:, 6] = 9.81
    return s


def preintegrate(reg, s, **kw):
    return imuconv.preintegrate(reg, s, bg=ZERO, ba=ZERO, noise=kw.pop("noise", NOISE), propagator="rk4", **kw)


def test_clean_samples_pass(reg):
    m = preintegrate(reg, samples())
    assert m.dt == pytest.approx(1.0, abs=1e-12)  # 200 steps of 5 ms, round-off only


def test_nanosecond_stamps_are_refused_naming_the_unit(reg):
    # EuRoC rows as they are in the file: t in integer nanoseconds (2e8 s steps read as seconds).
    s = samples()
    s[:, 0] = 1403715273262142976 + np.arange(len(s)) * 5_000_000
    # float64 holds 1.4e18 to 256 ns, so the median period is 5e6 "s" give or take that.
    with pytest.raises(ValueError, match="samples: the median period is 4.999.*e\\+06 s .*look like nanoseconds, but "
                                         "the samples' t must be in seconds"):
        preintegrate(reg, s)


def test_a_gap_is_refused_unless_allowed(reg):
    s = samples()
    s[100:, 0] += 10.0  # 10 s without samples
    with pytest.raises(ValueError, match="samples: row 100: gap of 10.005 s before this sample.*allow_gaps=True"):
        preintegrate(reg, s)
    assert preintegrate(reg, s, allow_gaps=True).dt == pytest.approx(11.0, abs=1e-9)


def test_nan_in_the_middle_names_the_row_and_column(reg):
    s = samples()
    s[57, 5] = np.nan
    with pytest.raises(ValueError, match="samples: row 57: ay is not finite"):
        preintegrate(reg, s)


def test_huge_accelerometer_value_is_an_error_not_inf(reg):
    s = samples()
    s[10, 4] = 1e308
    with pytest.raises(ValueError, match="preintegrate: produced a non-finite number"):
        preintegrate(reg, s)


def test_huge_noise_is_refused_before_integrating(reg):
    with pytest.raises(ValueError, match="noise: gyro_noise_density = 1e\\+160 is too large"):
        preintegrate(reg, samples(), noise=dict(NOISE, gyro_noise_density=1e160))


def test_huge_covariance_propagates_to_an_error_not_inf(reg):
    x = imuconv.State(q_wxyz=[1, 0, 0, 0])
    m = preintegrate(reg, samples())
    cov = 1e308 * np.eye(15)
    with pytest.raises(ValueError, match="propagate_by_preintegration: produced a non-finite number"):
        imuconv.propagate_by_preintegration(reg, m, x, cov, "left")
    with pytest.raises(ValueError, match="propagate: produced a non-finite number"):
        imuconv.propagate(reg, "rk4", "left", x, cov, samples(), noise=NOISE)


def write_inline_pipeline(path, s, keyframes, extra=None):
    doc = {"noise": NOISE, "imu": {"format": "inline", "samples": s.tolist()},
           "tasks": [{"type": "preintegrate", "name": "kf", "method": {"propagator": "rk4"},
                      "conventions": ["gtsam_manifold"], "keyframes": keyframes}]}
    doc.update(extra or {})
    path.write_text(json.dumps(doc))
    return str(path)


def test_keyframes_finer_than_the_samples_fail_fast(tmp_path):
    # 2.1e-7 s (0.21 s in the wrong unit) over 1 s of 200 Hz: 4.8 million intervals, almost all
    # between two samples. Refused before any is integrated, naming the step and the period.
    p = write_inline_pipeline(tmp_path / "fine.json", samples(), {"start": 0.0, "end": 1.0, "step": 2.1e-7})
    with pytest.raises(imuconv.Error, match="holds no IMU sample: the keyframe step is 2.1e-07 s, the IMU period "
                                            "0.005 s"):
        imuconv.run(p)


def test_sub_sample_keyframes_run_when_meant(tmp_path):
    kf = [0.1001, 0.1012, 0.1024]  # both intervals strictly between the samples at 0.1 and 0.105
    with pytest.raises(imuconv.Error, match="interval 0 \\[0.1001, 0.1012\\] s holds no IMU sample"):
        imuconv.run(write_inline_pipeline(tmp_path / "sub.json", samples(), kf))
    out = imuconv.run(write_inline_pipeline(tmp_path / "meant.json", samples(), kf, {"allow_empty_intervals": True}))
    assert out["tasks/kf/measurements/dt"].shape == (2,)


def test_check_accepts_a_keyframe_a_rounding_off_a_sample(reg, tmp_path):
    # 3 * 0.1 = 0.30000000000000004 lies 4e-17 s after the sample at 0.3: that sample (window.h,
    # kSameInstant). Before, Basalt's reference rounded both knots to one nanosecond and refused,
    # and the whole check failed.
    s = samples()
    t_end = 3 * 0.1
    assert t_end != 0.3 and 0.3 in s[:, 0]
    m = preintegrate(reg, s, t_start=0.2, t_end=t_end).express(reg, "gtsam_manifold")
    meas = {"measurements": [{
        "t_start": 0.2, "t_end": t_end, "dt": m.dt,
        "bias_estimate": {"bg": [0, 0, 0], "ba": [0, 0, 0]},
        "delta": {"R": m.delta_R.tolist(), "dp": m.dp.tolist(), "dv": m.dv.tolist()},
        "J_bias": {"matrix": m.J_bias.tolist()},
        "cov": {"convention": "gtsam_manifold", "blocks": m.blocks, "matrix": m.cov.tolist()}}]}
    (tmp_path / "m.json").write_text(json.dumps(meas))
    (tmp_path / "case.json").write_text(json.dumps({"noise": NOISE, "imu": s.tolist()}))
    report = imuconv.check(reg, str(tmp_path / "m.json"), case=str(tmp_path / "case.json"))
    assert report["verdict"] == "consistent"
    (r,) = report["measurements"]
    assert r["best"]["scheme"] == "rk4" and "not_applicable" not in r
