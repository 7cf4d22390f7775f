"""Runs imuconv commands that print one JSON object (--json) and validates each output against a
schema with Debian's python3-jsonschema (Draft202012Validator), after checking that the schema is
itself a valid draft 2020-12 schema. Shared by the per-command schema tests of tests/cli."""
import json
import os
import subprocess

from jsonschema import Draft202012Validator


def validate_runs(schema_path, runs, summary):
    """runs: (name, argv, expected exit code); summary(doc) -> the text printed for a valid
    output. Returns the number of failures, each printed with its JSON path."""
    with open(schema_path) as f:
        schema = json.load(f)
    Draft202012Validator.check_schema(schema)
    validator = Draft202012Validator(schema)
    env = dict(os.environ)
    env.pop("IMUCONV_PLUGIN_PATH", None)
    failures = 0
    for name, argv, expected_exit in runs:
        p = subprocess.run(argv, capture_output=True, text=True, env=env)
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
            print(f"ok   {name}: {summary(doc)}")
    return failures
