#!/usr/bin/env python3
"""Validates `imuconv montecarlo --json` against schemas/montecarlo_output.schema.json with
Debian's python3-jsonschema (Draft202012Validator): the schema is itself a valid draft 2020-12
schema, and the output of a propagator, a native preintegrator, a method whose noise reading is
not the simulated one (vins_fusion_as_configured) and a deliberately scaled simulation all
validate. Exit code 0 when everything passes; each failure is printed with its JSON path.
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
    case = os.path.join(args.source_dir, "tests", "data", "reference", "cases", "smooth-0.json")
    common = [args.binary, "montecarlo", "--case", case, "--trials", "64", "--seed", "5", "--duration", "2", "--json"]
    runs = [
        (["--method", "rk4"], 0),
        (["--method", "manifold", "--convention", "vins_fusion"], 0),
        (["--method", "basalt"], 0),
        (["--method", "vins_fusion_as_configured"], 1),
        (["--method", "euler", "--noise-scale", "2"], 1),
    ]
    failures = validate_runs(os.path.join(args.source_dir, "schemas", "montecarlo_output.schema.json"),
                             [(" ".join(extra), common + extra, code) for extra, code in runs],
                             lambda doc: f"verdict {doc['verdict']}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
