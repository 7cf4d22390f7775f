#!/usr/bin/env python3
"""Checks the JSON Schemas in schemas/ and validates against them, with Debian's
python3-jsonschema (Draft202012Validator):
  - every schema is itself a valid draft 2020-12 schema;
  - every example pipeline examples/*.json validates against schemas/pipeline.schema.json;
  - every examples/**/*.measurements.json against schemas/measurements.schema.json, every
    examples/**/*.state.json against schemas/state.schema.json;
  - each example pipeline runs with the built binary (exit code 0) and its output validates
    against schemas/output.schema.json;
  - a few malformed pipelines are rejected by the schema (so that it is not vacuous).
Exit code 0 when everything passes; each failure is printed with the file and the JSON path.
"""
import argparse
import copy
import glob
import json
import os
import subprocess
import sys

import jsonschema
from jsonschema import Draft202012Validator


def load(path):
    with open(path) as f:
        return json.load(f)


def make_validators(schema_dir):
    store = {}
    for path in sorted(glob.glob(os.path.join(schema_dir, "*.schema.json"))):
        uri = "file://" + os.path.abspath(path)
        store[uri] = load(path)
    validators = {}
    for uri, schema in store.items():
        Draft202012Validator.check_schema(schema)
        resolver = jsonschema.RefResolver(base_uri=uri, referrer=schema, store=store)
        validators[os.path.basename(uri[len("file://"):])] = Draft202012Validator(schema, resolver=resolver)
    return validators


def errors_of(validator, doc):
    return sorted(validator.iter_errors(doc), key=lambda e: list(e.absolute_path))


def report(path, errs):
    for e in errs[:20]:
        where = "/" + "/".join(str(p) for p in e.absolute_path)
        print(f"FAIL {path}: {where}: {e.message[:300]}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source-dir", required=True)
    ap.add_argument("--binary", required=True)
    ap.add_argument("--work-dir", required=True)
    args = ap.parse_args()
    src = os.path.abspath(args.source_dir)
    os.makedirs(args.work_dir, exist_ok=True)
    v = make_validators(os.path.join(src, "schemas"))
    for name in ("pipeline.schema.json", "output.schema.json", "measurements.schema.json", "state.schema.json"):
        if name not in v:
            print(f"FAIL schemas/{name} is missing")
            return 1
    failures = 0
    checked = 0

    pipelines = sorted(p for p in glob.glob(os.path.join(src, "examples", "*.json"))
                       if not p.endswith((".state.json", ".measurements.json")))
    if not pipelines:
        print("FAIL no example pipelines found")
        return 1
    for path in pipelines:
        doc = load(path)
        errs = errors_of(v["pipeline.schema.json"], doc)
        checked += 1
        if errs:
            failures += 1
            report(path, errs)
            continue
        out = os.path.join(args.work_dir, os.path.basename(path).replace(".json", ".out.json"))
        if os.path.exists(out):
            os.remove(out)
        r = subprocess.run([args.binary, "run", path, "-o", out, "--quiet"], capture_output=True, text=True, timeout=240)
        if r.returncode != 0:
            failures += 1
            print(f"FAIL {path}: imuconv run exited with {r.returncode}: {r.stderr.strip()[:2000]}")
            continue
        errs = errors_of(v["output.schema.json"], load(out))
        checked += 1
        if errs:
            failures += 1
            report(out, errs)
        else:
            print(f"ok   {os.path.relpath(path, src)} and its output")

    for pattern, schema in (("*.measurements.json", "measurements.schema.json"), ("*.state.json", "state.schema.json")):
        for path in sorted(glob.glob(os.path.join(src, "examples", "**", pattern), recursive=True)):
            errs = errors_of(v[schema], load(path))
            checked += 1
            if errs:
                failures += 1
                report(path, errs)
            else:
                print(f"ok   {os.path.relpath(path, src)}")

    # An output without the omitted matrices still validates.
    light = load(os.path.join(src, "examples", "inline_basics.json"))
    light["omit"] = ["Phi", "cov", "J_bias", "R", "reference"]
    light_path = os.path.join(args.work_dir, "omit_all.json")
    with open(light_path, "w") as f:
        json.dump(light, f)
    out = os.path.join(args.work_dir, "omit_all.out.json")
    r = subprocess.run([args.binary, "run", light_path, "-o", out, "--quiet"], capture_output=True, text=True, timeout=240,
                       cwd=os.path.join(src, "examples"))
    checked += 1
    if r.returncode != 0:
        failures += 1
        print(f"FAIL {light_path}: imuconv run exited with {r.returncode}: {r.stderr.strip()[:2000]}")
    else:
        errs = errors_of(v["pipeline.schema.json"], light) + errors_of(v["output.schema.json"], load(out))
        if errs:
            failures += 1
            report(out, errs)
        else:
            print("ok   inline_basics.json with every matrix omitted, and its output")

    # The new keys are accepted where the reader accepts them.
    good = load(os.path.join(src, "examples", "inline_basics.json"))
    good["imu"]["max_gap_factor"] = 20
    good["imu"]["allow_gaps"] = False
    good["allow_plugin_override"] = False
    checked += 1
    errs = errors_of(v["pipeline.schema.json"], good)
    if errs:
        failures += 1
        report("inline_basics.json with max_gap_factor, allow_gaps, allow_plugin_override", errs)
    else:
        print("ok   schema accepts max_gap_factor, allow_gaps, allow_plugin_override")

    # The schema must reject what the C++ reader rejects (a sample of malformed pipelines).
    base = load(os.path.join(src, "examples", "inline_basics.json"))
    bad = []
    d = copy.deepcopy(base); d["tasks"][0]["propagatr"] = "rk4"; bad.append(("unknown task key", d))
    d = copy.deepcopy(base); d["colour"] = 1; bad.append(("unknown top-level key", d))
    d = copy.deepcopy(base); d["tasks"][0]["interval"]["t_end"] = "soon"; bad.append(("t_end not a number", d))
    d = copy.deepcopy(base); del d["noise"]; bad.append(("noise missing", d))
    d = copy.deepcopy(base); d["tasks"][1]["type"] = "integrate"; bad.append(("unknown task type", d))
    d = copy.deepcopy(base); d["imu"]["samples"][3] = [0.1, 1, 2]; bad.append(("short sample", d))
    d = copy.deepcopy(base); d["tasks"][1]["interval"] = {"t_start": 0, "t_end": 0.1}; bad.append(("interval and keyframes", d))
    d = copy.deepcopy(base); d["omit"] = ["phi"]; bad.append(("unknown omit name", d))
    d = copy.deepcopy(base); d["omit"] = ["Phi", "Phi"]; bad.append(("omit name twice", d))
    d = copy.deepcopy(base); d["imu"]["max_gap_factor"] = 1; bad.append(("max_gap_factor not > 1", d))
    d = copy.deepcopy(base); d["imu"]["allow_gaps"] = "yes"; bad.append(("allow_gaps not a boolean", d))
    d = copy.deepcopy(base); d["allow_plugin_override"] = 1; bad.append(("allow_plugin_override not a boolean", d))
    for what, doc in bad:
        checked += 1
        if not errors_of(v["pipeline.schema.json"], doc):
            failures += 1
            print(f"FAIL the pipeline schema accepts a malformed pipeline ({what})")
        else:
            print(f"ok   schema rejects: {what}")

    print(f"{checked} checks, {failures} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
