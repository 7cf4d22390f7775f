# Shared fixtures of the Python suite: the registry (built-in plugins of this build) and the
# ten reference cases with GTSAM's outputs, copied into tests/data/reference, so the suite needs nothing outside the repository.
import json
import os
import pathlib

import numpy as np
import pytest

import imuconv

DATA = pathlib.Path(os.environ.get("IMUCONV_TEST_DATA", pathlib.Path(__file__).resolve().parents[1] / "data"))
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
