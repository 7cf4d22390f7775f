#!/usr/bin/env python3
"""Validates `imuconv experiment --json` against schemas/experiment_output.schema.json with
Debian's python3-jsonschema (Draft202012Validator): the schema is itself a valid draft 2020-12
schema, and the output of each experiment alone, of both, and of the variants the tests use
(another propagator, the zoh input, subdivided propagator steps) all validate. Few short trials:
the schema judges the layout, not the numbers (tests/cli/experiment.cpp does).

Also --report: the HTML document is well-formed XML (xml.etree) holding the note's eight heatmaps,
each an SVG element, and nothing that loads (no script, no src or href)."""
import argparse
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

from schema_runs import validate_runs


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source-dir", required=True)
    ap.add_argument("--binary", required=True)
    args = ap.parse_args()
    common = ["--trials", "2", "--seed", "3", "--duration", "1", "--json"]
    runs = [
        (["preint-by-prop"], 0),
        (["prop-by-preint"], 0),
        (["both"], 0),
        (["both", "--propagator", "openvins_discrete", "--input", "zoh", "--propagator-substeps", "2"], 0),
    ]
    failures = validate_runs(os.path.join(args.source_dir, "schemas", "experiment_output.schema.json"),
                             [(" ".join(extra), [args.binary, "experiment"] + extra + common, code)
                              for extra, code in runs],
                             lambda doc: f"{len(doc['comparisons'])} comparisons")
    failures += check_report(args.binary)
    return 1 if failures else 0


def check_report(binary):
    with tempfile.TemporaryDirectory() as work:
        path = os.path.join(work, "figures.html")
        env = dict(os.environ)
        env.pop("IMUCONV_PLUGIN_PATH", None)
        p = subprocess.run([binary, "experiment", "both", "--trials", "2", "--seed", "3", "--duration", "1",
                            "--report", path], capture_output=True, text=True, env=env)
        if p.returncode != 0:
            print(f"FAIL --report: exit code {p.returncode}; stderr: {p.stderr[:500]}")
            return 1
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError as e:
            print(f"FAIL --report: not well-formed XML: {e}")
            return 1
        svgs = [e for e in root.iter() if e.tag.endswith("}svg") and e.tag.startswith("{http://www.w3.org/2000/svg")]
        loads = [e.tag for e in root.iter() if e.tag.endswith("}script") or "src" in e.attrib or "href" in e.attrib]
        if len(svgs) != 8 or loads:
            print(f"FAIL --report: {len(svgs)} SVG figures (expected 8), loading elements {loads[:5]}")
            return 1
        print("ok   --report: 8 heatmaps, well-formed, nothing loaded")
        return 0


if __name__ == "__main__":
    sys.exit(main())
