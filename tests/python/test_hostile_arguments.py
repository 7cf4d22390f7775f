# Hostile arguments found by the sweep of the built module (27 Nov): each call either answers
# with finite numbers or refuses with an error that names the call, the argument or the JSON
# pointer; a Ctrl-C is a KeyboardInterrupt, not bad input. Every test here failed on the code
# before its fix (the commit that added it says how).
import json
import os
import signal
import threading
import warnings

import numpy as np
import pytest

import imuconv
from conftest import DATA, EUROC_NOISE, euroc_slice, start_state

CASE = DATA / "reference" / "cases" / "smooth-0.json"


@pytest.fixture(scope="module")
def case():
    with open(CASE) as f:
        return json.load(f)


@pytest.fixture(scope="module")
def meas(reg, case):
    return imuconv.preintegrate(reg, np.array(case["imu"]), bg=[0, 0, 0], ba=[0, 0, 0],
                                noise=case["noise"], preintegrator="manifold")


# ---- P2: the Registry's chart methods never return inf or NaN

def test_state_retract_that_overflows_is_refused(reg, case):
    x = start_state(case)
    with pytest.raises(ValueError, match=r"^retract: produced a non-finite number \(x\)"):
        reg.retract("left", x, np.ones(15) * 1e308)
    d = np.zeros(15)
    d[0] = 1e200  # a rotation of 1e200 rad: its sine and cosine are finite, the chart's p, v not
    with pytest.raises(ValueError, match=r"^retract: produced a non-finite number"):
        reg.retract("left_invariant_se23", x, d)


def test_state_local_that_overflows_is_refused(reg):
    x = imuconv.State(p=[-1e308, 0, 0], q_wxyz=[1, 0, 0, 0])
    y = imuconv.State(p=[1e308, 0, 0], q_wxyz=[1, 0, 0, 0])
    with pytest.raises(ValueError, match=r"^local: produced a non-finite number \(d\)"):
        reg.local("left", x, y)


def test_increment_retract_that_overflows_is_refused(reg, meas):
    with pytest.raises(ValueError, match=r"^increment_retract: produced a non-finite number"):
        reg.increment_retract("gtsam_tangent", meas.delta, np.ones(15) * 1e308)


def test_covariance_and_transition_conversions_that_overflow_are_refused(reg, case):
    x = imuconv.State(q_wxyz=[1, 0, 0, 0])
    with pytest.raises(ValueError, match=r"^convert_covariance: produced a non-finite number"):
        reg.convert_covariance("left", "openvins_jpl", x, np.eye(15) * 1e308)
    # A finite Phi whose entries are near the largest double: J_e Phi J_s^-1 sums entries of
    # Phi (x_e is rotated and away from the origin), and two of 1.7e308 overflow.
    x_e = start_state(case)
    with pytest.raises(ValueError, match=r"^convert_transition: produced a non-finite number"):
        reg.convert_transition("left", "openvins_jpl", x, x_e, np.full((15, 15), 1.7e308))
    # Still computed when finite (the same calls at ordinary sizes).
    assert np.isfinite(reg.convert_covariance("left", "openvins_jpl", x, np.eye(15))).all()
    assert np.isfinite(reg.convert_transition("left", "openvins_jpl", x, x_e, np.eye(15))).all()


# ---- P3: bias_corrected_delta never returns a NaN increment

def test_bias_corrected_delta_that_overflows_is_refused(reg, meas):
    with pytest.raises(ValueError, match=r"^bias_corrected_delta: produced a non-finite number"):
        imuconv.bias_corrected_delta(reg, meas, "gtsam_manifold", bg=[1e300, 0, 0], ba=[0, 0, 0])
    d = imuconv.bias_corrected_delta(reg, meas, "gtsam_manifold", bg=[1e-3, 0, 0], ba=[0, 0, 0])
    assert np.isfinite(d.dR).all() and np.isfinite(d.dp).all() and np.isfinite(d.dv).all()


# ---- P4: noise that overflows the covariance is refused by check and optimize, as by
# preintegrate, propagate and the CLI

def test_check_and_optimize_refuse_noise_that_overflows(reg, case, meas):
    noise = dict(case["noise"])
    noise["gyro_noise_density"] = 1e160  # squared over a 5 ms period: 1e320 / 5e-3, past double
    samples = np.array(case["imu"])
    with pytest.raises(ValueError, match=r"^noise: gyro_noise_density = 1e\+160 is too large"):
        imuconv.check(reg, meas, samples=samples, noise=noise)
    if hasattr(imuconv, "optimize"):
        poses = np.array([[samples[0, 0], 0, 0, 0, 1, 0, 0, 0], [samples[-1, 0], 0, 0, 0, 1, 0, 0, 0]])
        with pytest.raises(ValueError, match=r"^noise: gyro_noise_density = 1e\+160 is too large"):
            imuconv.optimize(reg, samples, poses, noise=noise, keyframe_step=1.0)


# ---- P5: samples that look mistaken warn in every call that takes samples, as the CLI warns
# wherever it reads an IMU file

def swapped_warnings(call):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        call()
    return [str(w.message) for w in caught
            if issubclass(w.category, UserWarning) and "look swapped" in str(w.message)]


def test_swapped_gyro_and_accel_columns_warn_in_every_call(reg):
    samples, poses = euroc_slice()
    swapped = samples[:, [0, 4, 5, 6, 1, 2, 3]]
    window = dict(t_start=samples[0, 0], t_end=samples[0, 0] + 1.0)
    assert swapped_warnings(lambda: imuconv.preintegrate(
        reg, swapped, bg=[0, 0, 0], ba=[0, 0, 0], noise=EUROC_NOISE, preintegrator="manifold", **window))
    assert swapped_warnings(lambda: imuconv.propagate(
        reg, "euler", "left", imuconv.State(q_wxyz=[1, 0, 0, 0]), np.eye(15) * 1e-6, swapped,
        noise=EUROC_NOISE, **window))
    if hasattr(imuconv, "optimize"):
        assert swapped_warnings(lambda: imuconv.optimize(
            reg, swapped, poses[:, :8], noise=EUROC_NOISE, keyframe_step=1.0))
    # The slice as recorded warns nowhere.
    assert not swapped_warnings(lambda: imuconv.preintegrate(
        reg, samples, bg=[0, 0, 0], ba=[0, 0, 0], noise=EUROC_NOISE, preintegrator="manifold", **window))


# ---- P7: ground-truth quaternions follow one rule, the pipeline's (unit within 1e-3)

@pytest.mark.skipif(not hasattr(imuconv, "optimize"), reason="built without Ceres")
def test_pose_quaternions_follow_the_ground_truth_readers_rule(reg):
    samples, poses = euroc_slice()
    rows = poses[:, :8].copy()
    rows[:, 4:8] = np.round(rows[:, 4:8], 3)  # three digits: norms off by up to ~1e-3 / 2
    norm_error = np.abs(np.linalg.norm(rows[:, 4:8], axis=1) - 1.0)
    assert norm_error.max() > 1e-6 and norm_error.max() <= 1e-3
    out = imuconv.optimize(reg, samples, rows, noise=EUROC_NOISE, keyframe_step=2.0)
    assert np.isfinite(out["p"]).all()
    rows[3, 4:8] *= 1.002  # off by 2e-3: refused, as the CLI's readers refuse it
    with pytest.raises(ValueError, match=r"^poses: row 3: quaternion \(q_w, q_x, q_y, q_z\) has norm "
                                         r"1\.002\d*, expected 1 \(to 1e-3\)"):
        imuconv.optimize(reg, samples, rows, noise=EUROC_NOISE, keyframe_step=2.0)


# ---- P8: a number in a dict beyond double precision is an imuconv.Error with its pointer

def test_an_integer_beyond_double_in_a_dict_is_named_by_pointer(reg, meas, tmp_path):
    path = tmp_path / "m.json"
    imuconv.write_measurements(path, reg, meas, t_start=0.0)
    doc = json.loads(path.read_text())
    doc["measurements"][0]["dt"] = 10 ** 400
    beyond = r"^measurements \(dict\): /measurements/0/dt: expected a number within double precision"
    with pytest.raises(imuconv.Error, match=beyond):
        imuconv.check(reg, doc, case=CASE)
    # One measurement given alone is named as the document it becomes.
    with pytest.raises(imuconv.Error, match=beyond):
        imuconv.check(reg, doc["measurements"][0], case=CASE)


# ---- P9: a path is str, bytes or os.PathLike (returning either), the same everywhere

class BytesPath:
    def __init__(self, path):
        self.path = os.fsencode(path)

    def __fspath__(self):
        return self.path


def test_bytes_paths_are_the_paths_they_name(reg, case, meas, tmp_path):
    for n, path in enumerate([os.fsencode(tmp_path / "b.json"), BytesPath(tmp_path / "pb.json")]):
        imuconv.write_measurements(path, reg, meas, t_start=case["imu"][0][0])
        assert (tmp_path / ("b.json", "pb.json")[n]).is_file()
        report = imuconv.check(reg, path, case=os.fsencode(CASE))
        assert report["verdict"]
        report = imuconv.check(reg, path, case=BytesPath(CASE))
        assert report["verdict"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.json", "pb.json"]
    # imuconv.run takes the same paths: the missing file is named as given, not as "b'...'".
    missing = tmp_path / "missing.json"
    for path in (missing, os.fsencode(missing), BytesPath(missing)):
        with pytest.raises(imuconv.Error, match="^" + str(missing)):
            imuconv.run(path)
    # What is not a path, or a path the C library would cut short, is refused by name.
    with pytest.raises(ValueError, match=r"^path: expected a path \(str, bytes or os.PathLike\), got int"):
        imuconv.write_measurements(3, reg, meas)
    with pytest.raises(ValueError, match=r"^path: the path contains a NUL character"):
        imuconv.write_measurements(str(tmp_path / "a\0b.json"), reg, meas)
    with pytest.raises(ValueError, match=r"^case: the path contains a NUL character"):
        imuconv.check(reg, meas, case=os.fsencode(CASE) + b"\0x")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.json", "pb.json"]


# ---- P10: Ctrl-C while blocked opening a FIFO is a KeyboardInterrupt

@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs")
def test_an_interrupted_fifo_write_is_a_keyboard_interrupt(reg, meas, tmp_path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    main = threading.get_ident()
    done = threading.Event()

    def interrupt():
        # SIGINT to the main thread, blocked in open(); should it not return, a reader opened
        # after the event times out unblocks it, so the test cannot hang.
        if not done.wait(0.3):
            signal.pthread_kill(main, signal.SIGINT)
        if not done.wait(10.0):
            fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
            done.wait(10.0)
            os.close(fd)

    helper = threading.Thread(target=interrupt)
    helper.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            imuconv.write_measurements(fifo, reg, meas, t_start=0.0)
    finally:
        done.set()
        helper.join()
    assert [p.name for p in tmp_path.iterdir()] == ["fifo"]  # nothing left beside it


# ---- A plugin directory that does not exist is named in the warning, as the CLI names it

def test_a_missing_plugin_directory_is_named(tmp_path):
    missing = tmp_path / "no-such-plugins"
    with pytest.warns(RuntimeWarning, match="^imuconv: " + str(missing) + ": plugin directory does not exist"):
        r = imuconv.Registry([str(missing)])
    assert r.load_issues[0]["file"] == str(missing)
