#!/usr/bin/env python3
"""The pipeline's folders are layers (docs/map.md): apps/pipeline/src/<layer>/ and the public
headers in apps/pipeline/include/imuconv/pipeline/ (each given its layer below), in the order

    io -> data -> forms -> spec -> tasks -> run

A file may include a file of its own layer or of a layer before it, never one after it (that
include "climbs back up"). Also checked, from the quoted includes and the definitions:
  - every source file is in a layer folder, and every public header has a layer here;
  - no circle of includes between files;
  - what a header declares is defined by the source files of its own stem (x.h by x.cpp; a
    public header by src/<layer>/x.cpp), so that a header never declares what another file
    implements beside what it uses from it (the circle json_check.cpp <-> json_parse.cpp had:
    ParseJsonFile declared beside the Checker it reports through). The few headers that gather
    several files' forms are listed in GATHERING with the files that implement them.
And for the pipeline's users: the command line, the other commands' libraries and the Python
module (apps/, python/src/) include only its public headers, never a file of apps/pipeline/src/,
and no CMake target puts apps/ itself on its include path (each library exports its own
include/ folder instead).
Each problem is printed as "FILE: ..." naming the include or the declaration; exit code 1 if
there is one, 0 otherwise. Reads only the sources (no build needed); takes well under a second.
"""
import argparse
import os
import re
import sys

LAYERS = ["io", "data", "forms", "spec", "tasks", "run"]

# The layer of each public header (apps/pipeline/include/imuconv/pipeline/), by what it declares.
PUBLIC = {
    "errors.h": "io",                # ConfigError, ReadError
    "file_digest.h": "io",
    "input_registry.h": "io",
    "input_start.h": "io",           # the first bytes of an input, opened as every input is
    "json_check.h": "io",            # Node and Checker
    "json_parse.h": "io",            # ParseJsonFile, ParseJsonText, ReadJsonFileAs
    "json_writer.h": "io",
    "matrix_rows.h": "io",           # a matrix as JSON rows (header-only: refcase writes with it)
    "output_file.h": "io",
    "result_arrays.h": "io",         # the NPZ arrays of an output document
    "standard_descriptors.h": "io",
    "text_sink.h": "io",
    "imu_plausibility.h": "data",
    "ground_truth_quaternion.h": "data",  # the ground-truth quaternion rule (header-only: Python too)
    "imu_reader.h": "data",
    "interval_samples.h": "data",    # intervals holding no IMU sample (run and optimize)
    "kalibr_yaml.h": "data",         # noise from a Kalibr imu.yaml
    "sample_checks.h": "data",
    "timing.h": "data",
    "json_io.h": "forms",            # the JSON forms of states, noise and matrices
    "measurement.h": "forms",        # the measurement form (imuconv check and Python read it too)
    "omit.h": "forms",               # what an output leaves out
    "block_labels.h": "forms",       # a chart's navigation and bias labels
    "run_options.h": "tasks",        # what the tasks run with (threads, limits, step callback)
    "check_evaluator.h": "tasks",    # the check task's evaluator, registered from above
    "optimize_evaluator.h": "tasks",  # the optimize task's solve, registered from above
    "registered_from_above.h": "tasks",  # the slot each of the two above is kept in
    "pipeline.h": "run",             # Pipeline, Run, RunToText, RunToArrays
    "pipeline_data.h": "run",        # a loaded Pipeline's data, outside a run
    "shard_merge.h": "run",
}

# Headers that gather the forms of several files (header -> the files that define them, besides
# a file of the header's own stem), each file in the header's layer.
GATHERING = {
    "include/imuconv/pipeline/json_io.h": {"src/forms/state.cpp", "src/forms/noise.cpp",
                                            "src/forms/chart_matrix.cpp", "src/forms/increment.cpp",
                                            "src/forms/json_io.cpp"},
    # ConfigError and ReadError are defined with the Checker that makes them (one message format).
    "include/imuconv/pipeline/errors.h": {"src/io/json_check.cpp"},
    # The readers of every data format, one file per format.
    "include/imuconv/pipeline/imu_reader.h": {"src/data/imu_reader.cpp", "src/data/ground_truth.cpp",
                                               "src/data/time_value.cpp"},
    # Task kinds: the interface's defaults and the list of kinds.
    "src/tasks/task.h": {"src/tasks/kinds.cpp"},
    # The output file's signal handler is defined beside the table of live temporaries it reads.
    "include/imuconv/pipeline/output_file.h": {"src/io/live_temporaries.cpp"},
    # The loaded pipeline (pipeline.cpp) and running it (run.cpp: the stages).
    "include/imuconv/pipeline/pipeline.h": {"src/run/run.cpp"},
    # The NPZ output: the arrays (result_arrays.cpp) and the archive (result_npz.cpp); the
    # collector is defined in the one file that uses it.
    "include/imuconv/pipeline/result_arrays.h": {"src/io/result_npz.cpp"},
    "src/io/array_collector.h": {"src/io/result_arrays.cpp"},
}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
# A declaration at namespace scope (column 0): "Type Name(" or "Type Name = ..." is not; only
# functions and classes are looked at.
DECL_FUNC = re.compile(r"^(?!return\b|using\b|typedef\b|#|//|namespace\b|template\b|\}|friend\b)"
                       r"[A-Za-z_][\w:<>,\s\*&]*?[\s\*&](\w+)\s*\(", re.M)
DECL_CLASS = re.compile(r"^(?:class|struct)\s+(\w+)(?:\s+final)?\s*(?::[^;{]*)?\{", re.M)
DEF_MEMBER = re.compile(r"^[^\s#/][^;]*?\b(\w+)::~?\w+\s*\(", re.M)


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def without_anonymous_namespaces(text):
    """The text less every "namespace { ... }" (file-local definitions are no header's)."""
    out, i = [], 0
    for m in re.finditer(r"\bnamespace\s*\{", text):
        if m.start() < i:
            continue
        out.append(text[i:m.start()])
        depth, j = 1, m.end()
        while j < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        i = j
    out.append(text[i:])
    return "".join(out)


def layer_of(rel):
    parts = rel.split("/")
    if parts[0] == "src":
        return parts[1] if len(parts) > 2 and parts[1] in LAYERS else None
    return PUBLIC.get(parts[-1])


def consumer_problems(source_dir):
    """Files of apps/ (outside apps/pipeline/) and python/src/ that include a private header of
    the pipeline; CMake files that put apps/ on a target's include path."""
    problems = []
    private = os.path.join(source_dir, "apps", "pipeline", "src") + os.sep
    for top in ("apps", os.path.join("python", "src")):
        for d, _, names in os.walk(os.path.join(source_dir, top)):
            if (d + os.sep).startswith(os.path.join(source_dir, "apps", "pipeline") + os.sep):
                continue
            for n in names:
                path = os.path.join(d, n)
                if n.endswith((".h", ".cpp")):
                    for spelled in INCLUDE.findall(strip_comments(open(path, encoding="utf-8").read())):
                        target = os.path.normpath(os.path.join(d, spelled))
                        if target.startswith(private) or "pipeline/src/" in spelled:
                            rel = os.path.relpath(path, source_dir)
                            problems.append(f'{rel}: includes "{spelled}", a private header of the pipeline '
                                            "(use its public header, include/imuconv/pipeline/)")
    for top in ("apps", "python", "tests", "bench"):
        for d, _, names in os.walk(os.path.join(source_dir, top)):
            for n in names:
                if n == "CMakeLists.txt" or n.endswith(".cmake"):
                    path = os.path.join(d, n)
                    body = re.sub(r"#[^\n]*", "", open(path, encoding="utf-8").read())
                    for m in re.finditer(r"target_include_directories\s*\(([^)]*)\)", body):
                        for token in m.group(1).replace("$<BUILD_INTERFACE:", " ").replace(">", " ").split():
                            dirname = os.path.normpath(token.replace("${PROJECT_SOURCE_DIR}", source_dir)
                                                       .replace("${CMAKE_CURRENT_SOURCE_DIR}", d))
                            if dirname == os.path.join(source_dir, "apps"):
                                rel = os.path.relpath(path, source_dir)
                                problems.append(f"{rel}: puts apps/ on an include path ({token}); include the "
                                                "library's public headers instead")
    return problems


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source-dir", required=True)
    root = os.path.join(ap.parse_args().source_dir, "apps", "pipeline")
    files = []
    for base in ("src", "include"):
        for d, _, names in os.walk(os.path.join(root, base)):
            files += [os.path.relpath(os.path.join(d, n), root) for n in names if n.endswith((".h", ".cpp"))]
    files.sort()
    present = set(files)
    text = {f: strip_comments(open(os.path.join(root, f), encoding="utf-8").read()) for f in files}
    problems = []

    for f in files:
        if layer_of(f) is None:
            if f.startswith("src/"):
                problems.append(f"{f}: not in a layer folder (src/{{{','.join(LAYERS)}}}/)")
            else:
                problems.append(f"{f}: a public header without a layer (add it to PUBLIC in {__file__})")

    def resolve(f, spelled):
        for cand in (os.path.join(os.path.dirname(f), spelled), os.path.join("include", spelled)):
            cand = os.path.normpath(cand)
            if cand in present:
                return cand
        return None

    edges = {}
    for f in files:
        for spelled in INCLUDE.findall(text[f]):
            t = resolve(f, spelled)
            if t is None:
                continue
            edges.setdefault(f, []).append(t)
            a, b = layer_of(f), layer_of(t)
            if a and b and LAYERS.index(b) > LAYERS.index(a):
                problems.append(f'{f}: includes "{spelled}", which is in layer {b}, above {a}: it climbs back up')

    # Circles of includes between files (depth-first search; each circle reported once).
    state, stack = {}, []

    def visit(f):
        state[f] = 1
        stack.append(f)
        for t in edges.get(f, []):
            if state.get(t) == 1:
                cyc = stack[stack.index(t):] + [t]
                problems.append(f"{f}: includes {t}, which closes a circle: " + " -> ".join(cyc))
            elif t not in state:
                visit(t)
        stack.pop()
        state[f] = 2

    for f in files:
        if f not in state:
            visit(f)

    # Where each header's functions and classes are defined.
    declared = {}
    for h in files:
        if h.endswith(".h"):
            body = text[h]
            for name in set(DECL_FUNC.findall(body)) | set(DECL_CLASS.findall(body)):
                declared.setdefault(name, []).append(h)
    for c in files:
        if not c.endswith(".cpp"):
            continue
        body = without_anonymous_namespaces(text[c])
        defined = set(DEF_MEMBER.findall(body))
        for line in body.splitlines():
            m = re.match(r"^(?!return\b|using\b|#|namespace\b|\}|static\b)[A-Za-z_][\w:<>,\s\*&]*?[\s\*&](\w+)\s*\(", line)
            if m and not line.rstrip().endswith(";"):
                defined.add(m.group(1))
        for name in defined:
            hs = declared.get(name, [])
            if len(hs) != 1:
                continue  # declared nowhere here, or in several headers (overloads): not judged
            h = hs[0]
            stem = os.path.splitext(os.path.basename(h))[0]
            own = os.path.splitext(os.path.basename(c))[0] == stem and (
                os.path.dirname(c) == os.path.dirname(h) or h.startswith("include/"))
            if own or c in GATHERING.get(h, ()):
                continue
            problems.append(f"{h}: declares {name}, which {c} defines: declare it in that file's own header")

    problems += consumer_problems(os.path.abspath(os.path.join(root, "..", "..")))

    for p in sorted(set(problems)):
        print(p)
    if problems:
        print(f"{len(set(problems))} problem(s) in the layers of apps/pipeline (see docs/map.md)")
        return 1
    print(f"apps/pipeline: {len(files)} files in layers {' -> '.join(LAYERS)}; nothing climbs back, no circle")
    return 0


if __name__ == "__main__":
    sys.exit(main())
