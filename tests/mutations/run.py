#!/usr/bin/env python3
"""Tests of the tests: apply each mutation of mutations.txt to the source tree, rebuild only
the targets it names in a given build directory, run the tests it names, and expect them to
fail. One line per mutation (caught / MISSED / ...); exit status 1 if any is missed, 2 if the
list or the tree is not usable. Run on demand, never from ctest (tests/mutations/README.md).

    tests/mutations/run.py BUILD_DIR [--only NAME_SUBSTRING] [--jobs N]

Each mutated file is restored byte for byte whatever happens (normal end, a failure, an
exception, Ctrl-C, SIGTERM, SIGHUP), and the targets are rebuilt from the restored tree at the
end, so the build directory holds no mutated binary afterwards. The restored file gets a new
modification time on purpose: with the old one, make would keep the mutated objects.
"""

import argparse
import os
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_ROOT = os.path.dirname(os.path.dirname(HERE))
LIST_FILE = os.path.join(HERE, "mutations.txt")
TEST_TIMEOUT_S = 900  # a mutation that makes a test hang counts as caught (it did not pass)


class ListError(Exception):
    pass


def parse_list(path):
    """Blocks of `key: value` lines separated by blank lines; `#` starts a comment line.
    Keys: name, file, find, replace (once each), build (targets, space separated, once),
    expect (`EXECUTABLE GTEST_FILTER`, one or more: every one must fail)."""
    mutations, block, start = [], {}, 0
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for number, line in enumerate(lines + [""], start=1):
        if line.startswith("#"):
            continue
        if not line.strip():
            if block:
                for key in ("name", "file", "find", "replace", "build", "expect"):
                    if key not in block:
                        raise ListError(f"{path}:{start}: mutation lacks '{key}:'")
                mutations.append(block)
                block = {}
            continue
        key, sep, value = line.partition(": ")
        if not sep or key not in ("name", "file", "find", "replace", "build", "expect"):
            raise ListError(f"{path}:{number}: expected 'KEY: VALUE' with KEY one of name, file, find, "
                            f"replace, build, expect; got {line!r}")
        if not block:
            start = number
        if key == "expect":
            executable, _, gtest_filter = value.partition(" ")
            if not gtest_filter:
                raise ListError(f"{path}:{number}: expect needs 'EXECUTABLE GTEST_FILTER'")
            block.setdefault("expect", []).append((executable, gtest_filter))
        elif key in block:
            raise ListError(f"{path}:{number}: '{key}:' given twice in one mutation")
        else:
            block[key] = value
    return mutations


class Restorer:
    """Keeps the original bytes of the mutated file and puts them back exactly once."""

    def __init__(self):
        self.path, self.original = None, None

    def mutate(self, path, original, mutated):
        self.path, self.original = path, original
        write_bytes(path, mutated)

    def restore(self):
        if self.path is not None:
            write_bytes(self.path, self.original)
            self.path, self.original = None, None


def write_bytes(path, data):
    # Through a temporary beside it and a rename: an interrupted write never leaves half a file.
    temporary = path + ".mutation-tmp"
    with open(temporary, "wb") as f:
        f.write(data)
        f.flush()
        os.fsync(f.fileno())
    os.replace(temporary, path)


def build(build_dir, targets, jobs, log):
    command = ["cmake", "--build", build_dir, "-j", str(jobs), "--target"] + targets
    return subprocess.run(command, stdout=log, stderr=subprocess.STDOUT).returncode == 0


def run_tests(build_dir, executable, gtest_filter, log):
    """'passed', 'failed', 'timeout' or 'no test' (a filter that matches nothing passes
    vacuously, which would hide a stale list entry)."""
    path = os.path.join(build_dir, "bin", executable)
    if not os.path.exists(path):
        return "no executable"
    try:
        result = subprocess.run([path, "--gtest_filter=" + gtest_filter], cwd=build_dir,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=TEST_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return "timeout"
    output = result.stdout.decode("utf-8", "replace")
    log.write(output.encode())
    log.flush()
    if "[==========] 0 tests" in output or "[==========] Running 0 tests" in output:
        return "no test"
    return "passed" if result.returncode == 0 else "failed"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("build_dir")
    parser.add_argument("--only", default="", help="run only the mutations whose name contains this")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--list", default=LIST_FILE)
    args = parser.parse_args()
    build_dir = os.path.abspath(args.build_dir)
    if not os.path.isfile(os.path.join(build_dir, "CMakeCache.txt")):
        print(f"{build_dir}: not a configured build directory (no CMakeCache.txt)", file=sys.stderr)
        return 2
    try:
        mutations = [m for m in parse_list(args.list) if args.only in m["name"]]
    except (ListError, OSError) as e:
        print(e, file=sys.stderr)
        return 2

    # Every entry must apply to this tree (its text found exactly once) before anything is
    # touched: a list that no longer matches the code is an error, not a silent pass.
    for m in mutations:
        path = os.path.join(SOURCE_ROOT, m["file"])
        try:
            count = open(path, "rb").read().count(m["find"].encode())
        except OSError as e:
            print(f"{m['name']}: {e}", file=sys.stderr)
            return 2
        if count != 1:
            print(f"{m['name']}: {m['file']} contains the text to replace {count} times, expected once: "
                  f"{m['find']!r}", file=sys.stderr)
            return 2

    log_path = os.path.join(build_dir, "mutations.log")
    restorer = Restorer()

    def on_signal(signum, _frame):
        restorer.restore()
        print(f"\ninterrupted (signal {signum}); the source tree is restored, but {build_dir} may hold "
              f"mutated binaries until its next build", file=sys.stderr)
        os._exit(128 + signum)

    for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(s, on_signal)

    all_targets = sorted({t for m in mutations for t in m["build"].split()})
    missed = 0
    with open(log_path, "wb") as log:
        try:
            # The named tests must pass on the tree as it is, or a failure proves nothing.
            if not build(build_dir, all_targets, args.jobs, log):
                print(f"the unmutated tree does not build ({log_path})", file=sys.stderr)
                return 2
            for m in mutations:
                for executable, gtest_filter in m["expect"]:
                    outcome = run_tests(build_dir, executable, gtest_filter, log)
                    if outcome != "passed":
                        print(f"{m['name']}: {executable} --gtest_filter={gtest_filter} is '{outcome}' on the "
                              f"unmutated tree ({log_path})", file=sys.stderr)
                        return 2
            for m in mutations:
                path = os.path.join(SOURCE_ROOT, m["file"])
                original = open(path, "rb").read()
                started = time.monotonic()
                restorer.mutate(path, original, original.replace(m["find"].encode(), m["replace"].encode(), 1))
                try:
                    log.write(f"\n=== {m['name']}\n".encode())
                    log.flush()
                    if not build(build_dir, m["build"].split(), args.jobs, log):
                        verdict, detail = "invalid", "the mutated tree does not build"
                    else:
                        outcomes = [(e, f, run_tests(build_dir, e, f, log)) for e, f in m["expect"]]
                        passed = [f"{e} {f}" for e, f, o in outcomes if o not in ("failed", "timeout")]
                        verdict = "caught" if not passed else "MISSED"
                        detail = ("every named test fails" if not passed else "still passing: " + "; ".join(passed))
                finally:
                    restorer.restore()
                if verdict != "caught":
                    missed += 1
                print(f"{verdict:8} {m['name']} ({m['file']}): {detail} [{time.monotonic() - started:.0f} s]",
                      flush=True)
        finally:
            restorer.restore()
            # Back to binaries of the unmutated tree (ccache makes this cheap).
            if not build(build_dir, all_targets, args.jobs, log):
                print(f"rebuilding the restored tree failed ({log_path})", file=sys.stderr)
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main())
