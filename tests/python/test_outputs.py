# The Python module and the standard descriptors (docs/outputs.md): a host process started with
# descriptors 0-2 closed must not hand their numbers to the files opened after `import imuconv`
# (a file given descriptor 1 would receive whatever is printed to "stdout"). The module's init
# opens /dev/null onto each closed one. Fails on 33f3aef: the file opened after the import is
# descriptor 0.
import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]

CHILD = r"""
import os, sys, json
import imuconv
report = sys.argv[1]
fd = os.open(report, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
result = imuconv.run(sys.argv[2], threads=1)
os.write(fd, json.dumps({"fd": fd, "keys": len(result),
                         "open": [os.path.exists(f"/proc/self/fd/{n}") for n in range(3)]}).encode())
os.close(fd)
"""


def run_child(tmp_path, close):
    report = tmp_path / "child.json"

    def closing():
        for n in close:
            os.close(n)

    proc = subprocess.run([sys.executable, "-c", CHILD, str(report), str(ROOT / "examples" / "inline_basics.json")],
                          preexec_fn=closing, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE if 2 not in close else subprocess.DEVNULL, timeout=120)
    assert proc.returncode == 0, proc.stderr
    import json
    return json.loads(report.read_text())


def test_import_with_stdout_closed_keeps_descriptor_1_for_stdout(tmp_path):
    got = run_child(tmp_path, close=[0, 1])
    assert got["fd"] > 2, got
    assert got["open"] == [True, True, True]
    assert got["keys"] > 0


def test_import_with_every_standard_descriptor_closed(tmp_path):
    # All three closed (a daemon's habit): the module still opens nothing onto 0-2, and runs.
    got = run_child(tmp_path, close=[0, 1, 2])
    assert got["fd"] > 2, got
    assert got["open"] == [True, True, True]
    assert got["keys"] > 0
