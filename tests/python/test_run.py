# imuconv.run: a pipeline's result as NumPy arrays, the same keys and bits as
# `imuconv run -o OUT.npz` (checked against numpy.load of the tool's archive) and as the JSON
# output's numbers; errors name the file and pointer.
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import imuconv

ROOT = pathlib.Path(__file__).resolve().parents[2]
BINARY = os.environ.get("IMUCONV_BINARY")


@pytest.mark.skipif(not BINARY, reason="IMUCONV_BINARY (the built imuconv) is set by ctest")
@pytest.mark.parametrize("example", ["inline_basics.json", "euroc_v1_01_keyframes.json"])
def test_run_equals_the_tools_npz_and_json(tmp_path, example):
    pipeline = str(ROOT / "examples" / example)
    result = imuconv.run(pipeline, threads=1)
    subprocess.run([BINARY, "run", pipeline, "-o", str(tmp_path / "out.npz"), "--quiet"], check=True)
    subprocess.run([BINARY, "run", pipeline, "-o", str(tmp_path / "out.json"), "--quiet"], check=True)
    with np.load(tmp_path / "out.npz") as z:
        assert sorted(z.files) == sorted(result)
        for key in z.files:
            if key == "meta":
                assert json.loads(str(z["meta"])) == result["meta"]
                continue
            assert z[key].dtype == result[key].dtype and z[key].shape == result[key].shape, key
            assert z[key].tobytes() == result[key].tobytes(), key  # bit for bit
    # One stacked key against the JSON text's numbers: every measurement's J_bias.
    doc = json.loads((tmp_path / "out.json").read_text())
    for task in doc["tasks"]:
        if task["type"] != "preintegrate":
            continue
        key = f"tasks/{task['name']}/measurements/J_bias/matrix"
        if key not in result:
            continue
        expected = np.array([m["J_bias"]["matrix"] for m in task["measurements"]])
        assert result[key].tobytes() == expected.tobytes()


def test_run_errors_name_the_file_and_pointer(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"imu": {"format": "inline", "samples": [[0, 0, 0, 0, 0, 0, 9.81]]}, "tasks": [],
                               "colour": 1}))
    with pytest.raises(imuconv.Error, match="bad.json: /colour: unknown key 'colour'"):
        imuconv.run(str(bad))
    with pytest.raises(imuconv.Error, match="no_such.json"):
        imuconv.run(str(tmp_path / "no_such.json"))
