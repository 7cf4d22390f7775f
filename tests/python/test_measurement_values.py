# imuconv.check on values (a Preintegrated, an Expressed, a dict in the measurements file's
# form with NumPy arrays) over samples given as an array with their noise; write_measurements
# through the library's atomic output file; Expressed.J_bias_columns; the reprs; plausibility
# warnings on samples. Everything is judged against the file path the command line takes, or
# against facts that hold whatever the implementation (see each test).
import json
import math
import os
import pathlib
import re
import warnings

import numpy as np
import pytest

import imuconv

from conftest import load_case

ROOT = pathlib.Path(__file__).resolve().parents[2]
MEAS = ROOT / "examples" / "data" / "gtsam_smooth0_manifold.measurements.json"
CASE = ROOT / "tests" / "data" / "reference" / "cases" / "smooth-0.json"


def case_arrays(case_id="smooth-0"):
    case, _ = load_case(case_id)
    samples = np.array(case["imu"], dtype=float)
    return case, samples, case["noise"]


def euler_measurement(reg, case_id="smooth-0"):
    case, samples, noise = case_arrays(case_id)
    m = imuconv.preintegrate(reg, samples, bg=case["state_s"]["bg"], ba=case["state_s"]["ba"], noise=noise,
                             propagator="euler")
    return case, samples, noise, m


def test_a_preintegrated_value_is_checked_as_its_file_would_be(reg, tmp_path):
    case, samples, noise, m = euler_measurement(reg)
    # Over the samples as an array (t_start defaults to the first sample; t_end = t_start + dt).
    by_value = imuconv.check(reg, m, samples=samples, noise=noise)
    assert by_value["verdict"] == "consistent", by_value
    (r,) = by_value["measurements"]
    assert r["best"]["scheme"] == "euler"
    # The value and the same measurement written to a file, both checked over the case file:
    # the same report (the value goes through the writer and the reader the file does).
    f = tmp_path / "m.json"
    imuconv.write_measurements(f, reg, m, t_start=float(samples[0, 0]))
    by_file = imuconv.check(reg, str(f), case=CASE)
    assert by_file["verdict"] == "consistent"
    assert imuconv.check(reg, m, case=CASE) == by_file
    # A list of values, and an Expressed (taken back to the reference charts).
    e = m.express(reg, "gtsam_manifold")
    both = imuconv.check(reg, [m, e], case=CASE, t_start=[samples[0, 0], samples[0, 0]])
    assert both["verdict"] == "consistent"
    assert len(both["measurements"]) == 2


def test_a_dict_with_numpy_arrays_is_read_as_the_file(reg):
    doc = json.loads(MEAS.read_text())
    from_file = imuconv.check(reg, str(MEAS), case=str(CASE))
    m = doc["measurements"][0]
    as_arrays = {
        "t_start": np.float64(m["t_start"]), "t_end": m["t_end"], "dt": m["dt"],
        "bias_estimate": {k: np.array(v) for k, v in m["bias_estimate"].items()},
        "delta": {k: np.array(v) for k, v in m["delta"].items()},
        "J_bias": {"matrix": np.array(m["J_bias"]["matrix"])},
        "cov": {"convention": m["cov"]["convention"], "blocks": m["cov"]["blocks"], "matrix": np.array(m["cov"]["matrix"])},
    }
    assert imuconv.check(reg, as_arrays, case=str(CASE)) == from_file
    assert imuconv.check(reg, [as_arrays], case=str(CASE)) == from_file
    assert imuconv.check(reg, {"measurements": [as_arrays]}, case=str(CASE)) == from_file
    # The charts may be undeclared, as in a file: the check finds them.
    unknown = dict(as_arrays, cov={"convention": "unknown", "matrix": as_arrays["cov"]["matrix"]})
    found = imuconv.check(reg, unknown, case=str(CASE))
    assert found["measurements"][0]["best"]["convention"] == "gtsam_manifold"


def test_bad_values_are_refused_by_name(reg):
    case, samples, noise, m = euler_measurement(reg)
    with pytest.raises(ValueError, match="one of case= .* and samples="):
        imuconv.check(reg, m, case=CASE, samples=samples, noise=noise)
    with pytest.raises(ValueError, match="one of case= .* and samples="):
        imuconv.check(reg, m)
    with pytest.raises(ValueError, match="noise"):
        imuconv.check(reg, m, samples=samples)
    with pytest.raises(ValueError, match="noise= goes with samples="):
        imuconv.check(reg, m, case=CASE, noise=noise)
    with pytest.raises(ValueError, match="t_start: expected 1 start time"):
        imuconv.check(reg, m, case=CASE, t_start=[1.0, 2.0])
    with pytest.raises(ValueError, match=r"measurements\[0\]: expected a Preintegrated or an Expressed, got int"):
        imuconv.check(reg, 3, case=CASE)
    with pytest.raises(ValueError, match="finite"):
        imuconv.check(reg, {"dt": float("nan")}, case=CASE)
    # A malformed dict: the reader's message, with the value's name and the JSON pointer.
    with pytest.raises(imuconv.Error, match=r"measurements \(dict\).*/measurements/0"):
        imuconv.check(reg, {"dt": 1.0, "colour": "red"}, case=CASE)
    # A measurement outside the samples: refused, not judged.
    with pytest.raises(imuconv.Error):
        imuconv.check(reg, m, samples=samples, noise=noise, t_start=samples[-1, 0] + 100.0)


def test_write_measurements_round_trips_exactly_and_atomically(reg, tmp_path):
    case, samples, noise, m = euler_measurement(reg)
    f = tmp_path / "m.json"
    imuconv.write_measurements(str(f), reg, m, t_start=1.5, conventions=["gtsam_manifold"])
    doc = json.loads(f.read_text())
    (w,) = doc["measurements"]
    # Numbers are written shortest-round-trip (the JSON outputs' rule): read back bit for bit.
    assert w["t_start"] == 1.5 and w["t_end"] == 1.5 + m.dt and w["dt"] == m.dt
    assert np.array_equal(np.array(w["cov"]["matrix"]), m.cov)
    assert np.array_equal(np.array(w["J_bias"]["matrix"]), m.J_bias)
    assert w["cov"]["convention"] == "preint_reference"
    e = m.express(reg, "gtsam_manifold")
    assert np.array_equal(np.array(w["expressed"]["gtsam_manifold"]["cov"]["matrix"]), e.cov)
    # A failed write leaves the previous file as it was (the output is replaced atomically,
    # after everything was computed): an unknown convention, named with the nearest id.
    before = f.read_bytes()
    with pytest.raises(imuconv.Error, match=r"gtsam_Manifold.*did you mean 'gtsam_manifold'"):
        imuconv.write_measurements(f, reg, m, conventions=["gtsam_Manifold"])
    assert f.read_bytes() == before
    assert sorted(os.listdir(tmp_path)) == ["m.json"]  # no temporary left
    # A directory is not an output.
    with pytest.raises(imuconv.Error, match=re.escape(str(tmp_path))):
        imuconv.write_measurements(tmp_path, reg, m)
    with pytest.raises(ValueError, match="path"):
        imuconv.write_measurements(3, reg, m)


def test_J_bias_columns_name_the_columns_in_every_convention(reg):
    # A fact of every chart: the rotation increment does not depend on the accelerometer bias,
    # so J_bias's theta rows are exactly zero in the column block labelled 'ba' and not in the
    # one labelled 'bg' (there, about -dt times the right Jacobian: norm ~ dt sqrt(3)).
    case, samples, noise, m = euler_measurement(reg)
    seen_orders = set()
    for c in reg.ids("preint_convention"):
        e = m.express(reg, c)
        assert sorted(e.J_bias_columns) == ["ba", "bg"], (c, e.J_bias_columns)
        assert sorted(e.J_bias_rows) == ["p", "theta", "v"], (c, e.J_bias_rows)
        seen_orders.add(tuple(e.J_bias_columns))
        t = 3 * e.J_bias_rows.index("theta")
        ba = 3 * e.J_bias_columns.index("ba")
        bg = 3 * e.J_bias_columns.index("bg")
        # Zero to round-off: a chart whose conversion Jacobian has no analytic form goes through
        # Ridders' differences (accurate to ~1e-10 relative, registry/src/numeric_jacobian.h),
        # which may leave 1e-12-sized terms where the analytic form has exact zeros; 1e-8 of
        # the largest entry is far above those and far below the bg block (~dt).
        scale = np.abs(e.J_bias).max()
        assert np.abs(e.J_bias[t:t + 3, ba:ba + 3]).max() <= 1e-8 * scale, (c, e.J_bias[t:t + 3])
        assert np.linalg.norm(e.J_bias[t:t + 3, bg:bg + 3]) > 0.1 * m.dt, (c, e.J_bias[t:t + 3])
    # Both orders occur among the built-in conventions, so the labels are not a constant.
    assert seen_orders == {("bg", "ba"), ("ba", "bg")}, seen_orders


def test_reprs_say_what_the_value_is(reg):
    case, samples, noise, m = euler_measurement(reg)
    r = repr(reg)
    assert r.startswith("Registry(state_convention=[") and "'left'" in r and "load_issues=0)" in r
    for kind in ("preint_convention", "propagator", "preintegrator"):
        assert f"{kind}=[" in r
    p = repr(m)
    # The numbers are printed shortest-round-trip: they read back as the values.
    assert float(re.search(r"dt=([^,]+),", p).group(1)) == m.dt
    angle = float(re.search(r"rotation ([^ ]+) deg", p).group(1))
    w = abs(m.delta.q_wxyz[0])
    assert angle == pytest.approx(math.degrees(2.0 * math.acos(min(1.0, w))), rel=1e-9)  # two routes to the angle
    assert "cov (15, 15) in preint_reference" in p and "columns ['bg', 'ba']" in p
    e = m.express(reg, "gtsam_manifold")
    s = repr(e)
    assert s.startswith("Expressed(convention='gtsam_manifold', blocks=" + str(e.blocks))
    assert "J_bias_columns=" + str(e.J_bias_columns) in s
    d = repr(m.delta)
    assert d.startswith("Increment(rotation ") and "dp=[" in d and "dv=[" in d
    assert repr(imuconv.Increment(q_wxyz=[1, 0, 0, 0])) == "Increment(rotation 0 deg, dp=[0, 0, 0], dv=[0, 0, 0])"


def test_mistaken_samples_warn_with_their_evidence(reg):
    case, samples, noise, m = euler_measurement(reg)
    swapped = samples[:, [0, 4, 5, 6, 1, 2, 3]]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        report = imuconv.check(reg, m, samples=swapped, noise=noise)
    texts = [str(w.message) for w in caught if issubclass(w.category, UserWarning)]
    assert len(texts) == 1 and "look swapped" in texts[0], texts
    median_gyro = np.median(np.linalg.norm(swapped[:, 1:4], axis=1))
    assert f"median |gyro| {median_gyro:.4g}" in texts[0]
    assert report["warnings"] == [texts[0][len("imuconv: "):]]
    # The check still judges (the numbers disagree with these samples: inconsistent, not refused).
    assert report["verdict"] == "inconsistent"
    # Correct samples: no warning, no key.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert "warnings" not in imuconv.check(reg, m, samples=samples, noise=noise)
