# imuconv.check: the report of `imuconv check --json` from Python, on GTSAM's smooth-0
# measurement as shipped and with its covariance's blocks declared in the wrong order.
import json
import pathlib

import numpy as np
import pytest

import imuconv

ROOT = pathlib.Path(__file__).resolve().parents[2]
MEAS = ROOT / "examples" / "data" / "gtsam_smooth0_manifold.measurements.json"
CASE = ROOT / "tests" / "data" / "reference" / "cases" / "smooth-0.json"


def test_gtsams_measurement_is_consistent(reg):
    report = imuconv.check(reg, str(MEAS), case=str(CASE))
    assert report["verdict"] == "consistent"
    (m,) = report["measurements"]
    assert m["best"]["convention"] == "gtsam_manifold" and m["best"]["scheme"] == "euler"
    # GTSAM's zero-order hold is `euler`'s: round-off only (docs/check.md; measured 2.4e-14).
    assert m["best"]["cov"]["max_d"] <= 1e-9


def test_mislabelled_blocks_are_found_and_named(reg, tmp_path):
    doc = json.loads(MEAS.read_text())
    cov = doc["measurements"][0]["cov"]
    order = [3, 1, 2, 0, 4]  # the numbers' blocks are [ba, p, v, theta, bg]; the label stays
    C = np.array(cov["matrix"])
    idx = np.concatenate([np.arange(3 * b, 3 * b + 3) for b in order])
    cov["matrix"] = C[np.ix_(idx, idx)].tolist()
    bad = tmp_path / "permuted.measurements.json"
    bad.write_text(json.dumps(doc))
    report = imuconv.check(reg, str(bad), case=str(CASE))
    assert report["verdict"] == "inconsistent"
    (m,) = report["measurements"]
    assert m["best"]["blocks"] == ["ba", "p", "v", "theta", "bg"]
    assert any("ba, p, v, theta, bg" in f for f in m["findings"]), m["findings"]


def test_unusable_input_raises(reg, tmp_path):
    with pytest.raises(imuconv.Error, match="no_such"):
        imuconv.check(reg, str(tmp_path / "no_such.json"), case=str(CASE))
