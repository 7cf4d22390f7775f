# examples/python/reproduce_gtsam_case.py runs from a fresh interpreter with the module on
# PYTHONPATH and prints agreement with GTSAM within the reference bound (1e-8 in d) for both
# methods on every column.
import os
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_example_reproduces_gtsam():
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "python" / "reproduce_gtsam_case.py"), "jitter-1"],
                         check=True, capture_output=True, text=True, env=dict(os.environ)).stdout
    rows = [line for line in out.splitlines() if line.startswith(("propagator=", "preintegrator="))]
    assert len(rows) == 2, out
    for row in rows:
        ds = [float(x) for x in re.findall(r"\d\.\de[-+]\d+", row)]
        assert len(ds) == 5 and max(ds) <= 1e-8, row
    assert "openvins_jpl" in out and "gtsam_navstate" in out
