#!/usr/bin/env python3
"""Validates `imuconv nees --json` against schemas/nees_output.schema.json with Debian's
python3-jsonschema (Draft202012Validator): the schema is itself a valid draft 2020-12 schema, and
the output on the EuRoC V1_01 slice in examples/data validates for three propagators, a convention
with another block order and a stride, the noise read from a whole pipeline file (its /noise).
Exit code 0 when everything passes; each failure is printed with its JSON path.
"""
import argparse
import json
import os
import subprocess
import sys

from jsonschema import Draft202012Validator


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source-dir", required=True)
    ap.add_argument("--binary", required=True)
    args = ap.parse_args()
    with open(os.path.join(args.source_dir, "schemas", "nees_output.schema.json")) as f:
        schema = json.load(f)
    Draft202012Validator.check_schema(schema)
    validator = Draft202012Validator(schema)
    data = os.path.join(args.source_dir, "examples", "data")
    common = ["--imu", os.path.join(data, "V1_01_easy_imu0_slice.csv"),
              "--ground-truth", os.path.join(data, "V1_01_easy_groundtruth_vicon2gt_slice.csv"),
              # a whole pipeline: its /noise object is read
              "--noise", os.path.join(args.source_dir, "examples", "euroc_v1_01_keyframes.json"),
              "--windows", "0.2,0.5,1.0", "--json"]
    runs = [
        ["--method", "rk4"],
        ["--method", "euler"],
        ["--method", "rk4", "--convention", "forster"],
        ["--method", "midpoint", "--stride", "0.1"],
    ]
    failures = 0
    env = dict(os.environ)
    env.pop("IMUCONV_PLUGIN_PATH", None)
    for extra in runs:
        p = subprocess.run([args.binary, "nees"] + common + extra, capture_output=True, text=True, env=env)
        name = " ".join(extra)
        if p.returncode != 0:
            print(f"FAIL {name}: exit code {p.returncode}; stderr: {p.stderr[:500]}")
            failures += 1
            continue
        doc = json.loads(p.stdout)
        errs = sorted(validator.iter_errors(doc), key=lambda e: list(e.absolute_path))
        for e in errs[:20]:
            print(f"FAIL {name}: /" + "/".join(str(x) for x in e.absolute_path) + f": {e.message[:300]}")
        if errs:
            failures += 1
        else:
            print(f"ok   {name}: factors " + ", ".join(f"{w['factor']:.4g}" for w in doc["windows"]))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
