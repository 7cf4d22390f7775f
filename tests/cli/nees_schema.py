#!/usr/bin/env python3
"""Validates `imuconv nees --json` against schemas/nees_output.schema.json with Debian's
python3-jsonschema (Draft202012Validator): the schema is itself a valid draft 2020-12 schema, and
the output on the EuRoC V1_01 slice in examples/data validates for three propagators, a convention
with another block order and a stride, the noise read from a whole pipeline file (its /noise).
Exit code 0 when everything passes; each failure is printed with its JSON path.
"""
import argparse
import os
import sys

from schema_runs import validate_runs


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source-dir", required=True)
    ap.add_argument("--binary", required=True)
    args = ap.parse_args()
    data = os.path.join(args.source_dir, "examples", "data")
    common = [args.binary, "nees", "--imu", os.path.join(data, "V1_01_easy_imu0_slice.csv"),
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
    failures = validate_runs(os.path.join(args.source_dir, "schemas", "nees_output.schema.json"),
                             [(" ".join(extra), common + extra, 0) for extra in runs],
                             lambda doc: "factors " + ", ".join(f"{w['factor']:.4g}" for w in doc["windows"]))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
