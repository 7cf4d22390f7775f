#!/usr/bin/env python3
"""Checks the JSON Schemas in schemas/ and validates against them, with Debian's
python3-jsonschema (Draft202012Validator):
  - every schema is itself a valid draft 2020-12 schema;
  - every example pipeline examples/*.json validates against schemas/pipeline.schema.json;
  - every examples/**/*.measurements.json against schemas/measurements.schema.json, every
    examples/**/*.state.json against schemas/state.schema.json;
  - each example pipeline runs with the built binary (exit code 0) and its output validates
    against schemas/output.schema.json;
  - the hand checker's cases (tests/data/pipeline_cases) are judged the same way by
    schemas/pipeline.schema.json: accepted, rejected, or accepted while the checker rejects
    them by design (what a schema cannot know: plugin ids, times against the data, ...).
Exit code 0 when everything passes; each failure is printed with the file and the JSON path.
"""
import glob
import json
import os
import subprocess
import sys

import jsonschema
from jsonschema import Draft202012Validator

from run_args import parse_run_args


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


def verdict(name, errs, ok_text):
    """Prints the schema errors of `name` (returns 1) or "ok" with ok_text (returns 0)."""
    if errs:
        report(name, errs)
        return 1
    print(f"ok   {ok_text}")
    return 0


def run_pipeline(binary, path, out, cwd=None):
    """Runs `imuconv run path -o out`; returns the output document, or None (the failure
    printed)."""
    if os.path.exists(out):
        os.remove(out)
    r = subprocess.run([binary, "run", path, "-o", out, "--quiet"], capture_output=True, text=True, timeout=240, cwd=cwd)
    if r.returncode != 0:
        print(f"FAIL {path}: imuconv run exited with {r.returncode}: {r.stderr.strip()[:2000]}")
        return None
    return load(out)


def main():
    args = parse_run_args()
    src = os.path.abspath(args.source_dir)
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
        result = run_pipeline(args.binary, path, out)
        if result is None:
            failures += 1
            continue
        checked += 1
        failures += verdict(out, errors_of(v["output.schema.json"], result), f"{os.path.relpath(path, src)} and its output")

    for pattern, schema in (("*.measurements.json", "measurements.schema.json"), ("*.state.json", "state.schema.json")):
        for path in sorted(glob.glob(os.path.join(src, "examples", "**", pattern), recursive=True)):
            checked += 1
            failures += verdict(path, errors_of(v[schema], load(path)), os.path.relpath(path, src))

    # An output without the omitted matrices still validates.
    light = load(os.path.join(src, "examples", "inline_basics.json"))
    light["omit"] = ["Phi", "cov", "J_bias", "R", "reference"]
    light_path = os.path.join(args.work_dir, "omit_all.json")
    with open(light_path, "w") as f:
        json.dump(light, f)
    out = os.path.join(args.work_dir, "omit_all.out.json")
    result = run_pipeline(args.binary, light_path, out, cwd=os.path.join(src, "examples"))
    checked += 1
    if result is None:
        failures += 1
    else:
        errs = errors_of(v["pipeline.schema.json"], light) + errors_of(v["output.schema.json"], result)
        failures += verdict(out, errs, "inline_basics.json with every matrix omitted, and its output")

    # The batch example (examples/batch/) and the outputs of imuconv run --shard K/N, whose
    # first member "shard" the output schema describes.
    batch = os.path.join(src, "examples", "batch", "euroc_v1_01_windows.json")
    checked += 1
    failures += verdict(batch, errors_of(v["pipeline.schema.json"], load(batch)), os.path.relpath(batch, src))
    for k in (0, 1):
        out = os.path.join(args.work_dir, f"inline_basics.shard{k}.out.json")
        if os.path.exists(out):
            os.remove(out)
        r = subprocess.run([args.binary, "run", "inline_basics.json", "--shard", f"{k}/2", "-o", out, "--quiet"],
                           capture_output=True, text=True, timeout=240, cwd=os.path.join(src, "examples"))
        checked += 1
        if r.returncode != 0:
            failures += 1
            print(f"FAIL inline_basics.json --shard {k}/2: imuconv run exited with {r.returncode}: "
                  f"{r.stderr.strip()[:2000]}")
            continue
        result = load(out)
        errs = errors_of(v["output.schema.json"], result)
        if "shard" not in result:
            errs.append("no \"shard\" member")
        failures += verdict(out, errs, f"shard {k}/2 of inline_basics.json")

    # A check task's output (schemas/output.schema.json refers to check_output.schema.json):
    # GTSAM's numbers for the reference case smooth-0 over its samples given inline, as they
    # are (consistent: exit 0) and with the covariance doubled (inconsistent: exit 1, the
    # document written all the same).
    case = load(os.path.join(src, "tests", "data", "reference", "cases", "smooth-0.json"))
    meas = load(os.path.join(src, "examples", "data", "gtsam_smooth0_manifold.measurements.json"))
    for doubled in (False, True):
        if doubled:
            for m in meas["measurements"]:
                m["cov"]["matrix"] = [[2.0 * x for x in row] for row in m["cov"]["matrix"]]
        tag = "check_doubled" if doubled else "check"
        meas_path = os.path.join(args.work_dir, tag + ".measurements.json")
        with open(meas_path, "w") as f:
            json.dump(meas, f)
        doc = {"noise": case["noise"], "imu": {"format": "inline", "samples": case["imu"]},
               "tasks": [{"type": "check", "name": tag, "measurements": {"file": meas_path}}]}
        path = os.path.join(args.work_dir, tag + ".json")
        with open(path, "w") as f:
            json.dump(doc, f)
        out = os.path.join(args.work_dir, tag + ".out.json")
        if os.path.exists(out):
            os.remove(out)
        r = subprocess.run([args.binary, "run", path, "-o", out, "--quiet"], capture_output=True, text=True, timeout=240)
        checked += 1
        if r.returncode != (1 if doubled else 0) or not os.path.exists(out):
            failures += 1
            print(f"FAIL {path}: imuconv run exited with {r.returncode}: {r.stderr.strip()[:2000]}")
            continue
        result = load(out)
        errs = errors_of(v["pipeline.schema.json"], doc) + errors_of(v["output.schema.json"], result)
        if result["tasks"][0]["verdict"] != ("inconsistent" if doubled else "consistent"):
            errs.append(f"verdict {result['tasks'][0]['verdict']}")
        failures += verdict(out, errs, f"a check task ({tag}) and its output")

    # The hand checker's cases (tests/data/pipeline_cases/cases.json; the checker's verdicts
    # are asserted by tests/pipeline/schema_cases.cpp): the schema accepts accept/ and
    # semantic/ (rejected by the checker by design, for the reason each case gives) and
    # rejects reject/.
    cases_dir = os.path.join(src, "tests", "data", "pipeline_cases")
    cases = load(os.path.join(cases_dir, "cases.json"))["cases"]
    if len(cases) < 50:
        failures += 1
        print(f"FAIL {cases_dir}/cases.json lists only {len(cases)} cases")
    for case in cases:
        group = case["file"].split("/")[0]
        errs = errors_of(v["pipeline.schema.json"], load(os.path.join(cases_dir, case["file"])))
        checked += 1
        want_reject = group == "reject"
        if group not in ("accept", "reject", "semantic"):
            failures += 1
            print(f"FAIL {case['file']}: unknown group {group}")
        elif bool(errs) != want_reject:
            failures += 1
            if errs:
                report(case["file"] + f" (the checker {'accepts' if group == 'accept' else 'rejects it by design: ' + case.get('why', '')}; the schema rejects)", errs)
            else:
                print(f"FAIL {case['file']}: the checker rejects it at {case.get('pointer', '')!r}, the schema accepts it")
        else:
            print(f"ok   {case['file']}: schema {'rejects' if errs else 'accepts'}" +
                  (f" (checker rejects by design: {case['why']})" if group == "semantic" else ""))

    print(f"{checked} checks, {failures} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
