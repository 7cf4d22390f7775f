#!/usr/bin/python3
"""imuconv run -o OUT.npz against numpy.load, bit for bit.

Runs pipelines (every example, every accepted pipeline case, and one whose steps carry times
only in some elements) to JSON and to NPZ, loads the NPZ with numpy.load (allow_pickle=False,
the default) and the JSON with json.load, and checks that the archive holds exactly what the
rule of docs/interop.md derives from the JSON: the same keys, each array's dtype and shape, and
every number's 64 bits (json.load reads each number as Python does, the correctly rounded
double; the comparison is of the bit patterns, so -0.0 and 0.0 differ). The rule is derived
here again from the parsed document (a second implementation, independent of the C++ one).

Needs NumPy: run with Debian's /usr/bin/python3 (python3-numpy).
"""
import copy
import glob
import json
import os
import struct
import subprocess
import sys

import numpy as np

from run_args import parse_run_args

INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1


def escape(member):
    return member.replace("~", "~0").replace("/", "~1")


def join(prefix, segment):
    return segment if not prefix else prefix + "/" + segment


def is_int(v):
    return isinstance(v, int) and not isinstance(v, bool) and INT64_MIN <= v <= INT64_MAX


def is_number(v):
    return is_int(v) or isinstance(v, float)


def rectangular(v):
    """The shape of a rectangular array of numbers (at least one number), else None."""
    if is_number(v):
        return ()
    if not isinstance(v, list) or not v:
        return None
    shapes = [rectangular(e) for e in v]
    if shapes[0] is None or any(s != shapes[0] for s in shapes):
        return None
    return (len(v),) + shapes[0]


def flatten(v):
    return [x for e in v for x in flatten(e)] if isinstance(v, list) else [v]


class Expected:
    """What the archive must hold, derived from the parsed JSON document."""

    def __init__(self, doc):
        self.numbers = {}  # key -> list of (indices, levels, pointer, shape, flat values)
        self.values = {}  # key -> list of (indices, levels, pointer, value)
        self.aoo = {}  # array-of-objects key -> list of lengths (one per instance)
        self.walk(doc, "", "", (), (), top=True)

    def walk(self, v, key, pointer, indices, levels, top=False):
        if isinstance(v, dict):
            if not v and not top:
                self.values.setdefault(key, []).append((indices, levels, pointer, v))
            for member, x in v.items():
                m = escape(member)
                if top and member == "tasks" and isinstance(x, list) and x and isinstance(x[0], dict):
                    for task in x:
                        assert next(iter(task)) == "name", "a task's first member is its name"
                        name = "tasks/" + escape(task["name"])
                        self.walk(task, name, name, indices, levels)
                    continue
                self.walk(x, join(key, m), join(pointer, m), indices, levels)
            return
        if isinstance(v, list) and v and isinstance(v[0], dict):
            self.aoo.setdefault(key, []).append(len(v))
            for i, e in enumerate(v):
                assert isinstance(e, dict)
                self.walk(e, key, pointer + "/" + str(i), indices + (i,), levels + (key,))
            return
        shape = rectangular(v)
        if shape is None or (shape == () and not indices):
            self.values.setdefault(key, []).append((indices, levels, pointer, v))
        else:
            self.numbers.setdefault(key, []).append((indices, levels, pointer, shape, flatten(v)))

    def grid(self, occurrences):
        """The lengths of the arrays of objects when the occurrences fill their grid, else None."""
        levels = occurrences[0][1]
        if any(o[1] != levels for o in occurrences):
            return None
        dims, cells = [], 1
        for a in levels:
            lengths = self.aoo[a]
            if len(lengths) != cells or any(n != lengths[0] for n in lengths):
                return None
            dims.append(lengths[0])
            cells *= lengths[0]
        return dims if len(occurrences) == cells else None

    def arrays(self):
        out = {}
        for key, occ in self.numbers.items():
            flat = [x for o in occ for x in o[4]]
            real = any(isinstance(x, float) for x in flat)
            dtype = "<f8" if real else "<i8"
            if real:
                assert all(isinstance(x, float) or abs(x) <= 2**53 for x in flat), key
            dims = self.grid(occ)
            if dims is not None and all(o[3] == occ[0][3] for o in occ):
                out[key] = (np.array(flat, dtype=dtype).reshape(tuple(dims) + occ[0][3]), occ[0][1])
            else:
                for o in occ:
                    out[o[2]] = (np.array(o[4], dtype=dtype).reshape(o[3]), ())
        return out

    def sidecar_values(self):
        out = {}
        for key, occ in self.values.items():
            if self.grid(occ) is not None and all(same(o[3], occ[0][3]) for o in occ):
                out[key] = occ[0][3]
            else:
                for o in occ:
                    out[o[2]] = o[3]
        return out


def same(a, b):
    """Equal JSON values, numbers by type and bit pattern."""
    if type(a) is not type(b):
        return False
    if isinstance(a, float):
        return struct.pack("<d", a) == struct.pack("<d", b)
    if isinstance(a, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, dict):
        return list(a) == list(b) and all(same(a[k], b[k]) for k in a)
    return a == b


def check(json_path, npz_path):
    with open(json_path, encoding="utf-8") as f:
        doc = json.load(f)
    expected = Expected(doc)
    want = expected.arrays()
    problems = []
    with np.load(npz_path) as z:  # allow_pickle=False: the default
        files = list(z.files)
        if "meta" not in files:
            return ["no sidecar 'meta'"]
        meta_array = z["meta"]
        if meta_array.shape != () or meta_array.dtype.kind != "U":
            problems.append(f"meta: shape {meta_array.shape}, dtype {meta_array.dtype}")
        meta = json.loads(str(meta_array))
        got_keys = [k for k in files if k != "meta"]
        if sorted(got_keys) != sorted(want):
            problems.append(f"keys differ: missing {sorted(set(want) - set(got_keys))[:5]}, "
                            f"extra {sorted(set(got_keys) - set(want))[:5]}")
        n_numbers = 0
        for key in got_keys:
            if key not in want:
                continue
            a, (w, _) = z[key], want[key]
            n_numbers += a.size
            if a.dtype.str != w.dtype.str or a.shape != w.shape or not a.flags.c_contiguous:
                problems.append(f"{key}: {a.dtype.str} {a.shape}, expected {w.dtype.str} {w.shape}")
            elif a.tobytes() != w.tobytes():  # every number's 64 bits
                bad = np.flatnonzero(a.view("<u8").ravel() != w.view("<u8").ravel())
                problems.append(f"{key}: {bad.size} number(s) differ, first at flat index {bad[0]}")
    if meta.get("format") != "imuconv-npz" or meta.get("format_version") != 1:
        problems.append(f"sidecar format: {meta.get('format')} {meta.get('format_version')}")
    want_values = expected.sidecar_values()
    got_values = meta.get("values", {})
    if sorted(got_values) != sorted(want_values):
        problems.append(f"sidecar keys differ: missing {sorted(set(want_values) - set(got_values))[:5]}, "
                        f"extra {sorted(set(got_values) - set(want_values))[:5]}")
    for k, v in want_values.items():
        if k in got_values and not same(got_values[k], v):
            problems.append(f"sidecar value {k}: {str(got_values[k])[:60]}, expected {str(v)[:60]}")
    want_stacked = {k: list(levels) for k, (_, levels) in want.items() if levels}
    if meta.get("stacked_over") != want_stacked:
        problems.append("sidecar stacked_over differs")
    # Every number of the document is in an array or a sidecar value, none twice.
    total = sum(len(o[4]) for occ in expected.numbers.values() for o in occ)
    if n_numbers != total:
        problems.append(f"{n_numbers} numbers in the arrays, {total} in the JSON's arrays")
    return problems


def irregular_pipeline(source_dir, work):
    """The GTSAM import's measurement twice, the second without its times: the steps' t_start
    and t_end are then in element 0 only, and are written per element."""
    with open(os.path.join(source_dir, "examples/data/gtsam_smooth0_manifold.measurements.json")) as f:
        m = json.load(f)["measurements"][0]
    second = copy.deepcopy(m)
    del second["t_start"], second["t_end"]
    with open(os.path.join(work, "irregular.measurements.json"), "w") as f:
        json.dump({"measurements": [m, second]}, f)
    with open(os.path.join(source_dir, "examples/gtsam_import.json")) as f:
        p = json.load(f)
    task = p["tasks"][0]
    task["measurements"] = {"file": "irregular.measurements.json"}
    p["tasks"] = [task]
    p.pop("$schema", None)
    path = os.path.join(work, "irregular.json")
    with open(path, "w") as f:
        json.dump(p, f)
    return path


def main():
    a = parse_run_args()
    env = dict(os.environ)
    env.pop("IMUCONV_PLUGIN_PATH", None)
    # The examples (the whole EuRoC file aside: 34 MB) and the irregular pipeline must run; an
    # accepted pipeline case is one the schema and the checker accept, and may still fail to
    # run (its data is not there, by design): such a case is skipped when its JSON run fails.
    examples = sorted(glob.glob(os.path.join(a.source_dir, "examples", "*.json")))
    examples = [p for p in examples if not p.endswith(("euroc_v1_01_full.json", ".state.json"))]
    cases = sorted(glob.glob(os.path.join(a.source_dir, "tests/data/pipeline_cases/accept/*.json")))
    pipelines = examples + [irregular_pipeline(a.source_dir, a.work_dir)] + cases
    failures = 0
    per_element = 0
    for pipeline in pipelines:
        name = os.path.splitext(os.path.basename(pipeline))[0]
        out_json = os.path.join(a.work_dir, name + ".out.json")
        out_npz = os.path.join(a.work_dir, name + ".out.npz")
        out_flag = os.path.join(a.work_dir, name + ".out.bin")  # --format npz, no .npz extension
        for args in (["-o", out_json], ["-o", out_npz], ["--format", "npz", "-o", out_flag]):
            r = subprocess.run([a.binary, "run", pipeline, "-q"] + args, env=env, capture_output=True, text=True)
            if r.returncode != 0 and pipeline in cases and args[1] == out_json:
                print(f"skip {name}: the run itself fails: {r.stderr.strip()[:200]}")
                break
            if r.returncode != 0:
                print(f"FAIL {name}: imuconv run {' '.join(args)} exited {r.returncode}: {r.stderr.strip()}")
                failures += 1
                break
        else:
            with open(out_npz, "rb") as f1, open(out_flag, "rb") as f2:
                if f1.read() != f2.read():
                    print(f"FAIL {name}: --format npz and the .npz extension wrote different archives")
                    failures += 1
            problems = check(out_json, out_npz)
            with np.load(out_npz) as z:
                per_element += sum(1 for k in z.files if any(s.isdigit() for s in k.split("/")))
            for p in problems:
                print(f"FAIL {name}: {p}")
            failures += bool(problems)
            print(f"{'ok  ' if not problems else 'FAIL'} {name}")
    # The irregular pipeline must have exercised the per-element rule.
    if per_element == 0:
        print("FAIL: no archive held a per-element key")
        failures += 1
    print(f"{len(pipelines)} pipelines, {failures} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
