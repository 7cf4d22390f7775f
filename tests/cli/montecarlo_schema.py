#!/usr/bin/env python3
"""Validates `imuconv montecarlo --json` against schemas/montecarlo_output.schema.json with
Debian's python3-jsonschema (Draft202012Validator): the schema is itself a valid draft 2020-12
schema, and the output of a propagator, a native preintegrator, a method whose noise reading is
not the simulated one (vins_fusion_as_configured) and a deliberately scaled simulation all
validate. Exit code 0 when everything passes; each failure is printed with its JSON path.
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
    with open(os.path.join(args.source_dir, "schemas", "montecarlo_output.schema.json")) as f:
        schema = json.load(f)
    Draft202012Validator.check_schema(schema)
    validator = Draft202012Validator(schema)
    case = os.path.join(args.source_dir, "tests", "data", "reference", "cases", "smooth-0.json")
    runs = [
        (["--method", "rk4"], 0),
        (["--method", "manifold", "--convention", "vins_fusion"], 0),
        (["--method", "basalt"], 0),
        (["--method", "vins_fusion_as_configured"], 1),
        (["--method", "euler", "--noise-scale", "2"], 1),
    ]
    failures = 0
    env = dict(os.environ)
    env.pop("IMUCONV_PLUGIN_PATH", None)
    for extra, expected_exit in runs:
        cmd = [args.binary, "montecarlo", "--case", case, "--trials", "64", "--seed", "5", "--duration", "2",
               "--json"] + extra
        p = subprocess.run(cmd, capture_output=True, text=True, env=env)
        name = " ".join(extra)
        if p.returncode != expected_exit:
            print(f"FAIL {name}: exit code {p.returncode}, expected {expected_exit}; stderr: {p.stderr[:500]}")
            failures += 1
            continue
        doc = json.loads(p.stdout)
        errs = sorted(validator.iter_errors(doc), key=lambda e: list(e.absolute_path))
        for e in errs[:20]:
            print(f"FAIL {name}: /" + "/".join(str(x) for x in e.absolute_path) + f": {e.message[:300]}")
        if errs:
            failures += 1
        else:
            print(f"ok   {name}: verdict {doc['verdict']}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
