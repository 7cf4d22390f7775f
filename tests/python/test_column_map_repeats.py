# A pipeline whose IMU column map reads one column for two axes is refused by imuconv.run at
# the JSON pointer, as `imuconv run` refuses it: the check is the library's (spec/sources.cpp).
import json
import pathlib

import pytest

import imuconv

REPO = pathlib.Path(__file__).resolve().parents[2]


def test_run_refuses_one_column_for_two_axes(tmp_path):
    pipeline = {
        "noise": {"gyro_noise_density": 1.6968e-04, "accel_noise_density": 2.0e-3,
                  "gyro_random_walk": 1.9393e-05, "accel_random_walk": 3.0e-3},
        "imu": {"format": "csv", "path": str(REPO / "examples/data/generic_imu_seconds.csv"), "delimiter": ";",
                "header_rows": 1, "time_unit": "s",
                "columns": {"t": "time", "ax": "ax", "ay": "ay", "az": "az", "wx": 4, "wy": 4, "wz": 6}},
        "tasks": [{"type": "preintegrate", "name": "kf", "method": {"preintegrator": "tangent"},
                   "keyframes": [0.0, 0.5, 1.0]}]}
    p = tmp_path / "c.json"
    p.write_text(json.dumps(pipeline))
    with pytest.raises(imuconv.Error, match="c.json: /imu/columns/wy: column 4 is already used for 'wx'"):
        imuconv.run(str(p))
