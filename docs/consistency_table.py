#!/usr/bin/env python3
"""Writes the cross-system consistency table of docs/consistency.md from `imuconv montecarlo
--json` outputs named METHOD.CASE.json in one folder (the command that makes them is in
docs/consistency.md). Usage: consistency_table.py FOLDER"""
import json
import math
import sys
from pathlib import Path

SYSTEMS = [("GTSAM", ["manifold", "tangent"]), ("VINS-Fusion", ["vins_fusion"]),
           ("Basalt", ["basalt"]), ("OpenVINS", ["openvins_discrete"]),
           ("ORB-SLAM3", ["orb_slam3"]), ("OKVIS2", ["okvis2", "okvis2_step_local"]),
           ("FAST-LIO2", ["fast_lio2", "fast_lio2_exact_rotation"]),
           ("(exact reference)", ["midpoint"])]
CASES = ["static-0", "smooth-0", "smooth-1", "smooth-2", "smooth-3", "white-0", "aggressive-0",
         "aggressive-1", "jitter-0", "jitter-1"]


def load(folder, method, case):
    path = Path(folder) / f"{method}.{case}.json"
    return json.loads(path.read_text()) if path.exists() and path.stat().st_size else None


def cell(r):
    mark = "ok" if r["verdict"] == "consistent" else "**X**"
    return f"{mark} {r['nees_mean']:.1f}"


def worst_block(r):
    """The block whose predicted variance is furthest from the sampled one (ratio sampled /
    predicted, as montecarlo reports it), and that ratio."""
    b = max(r["blocks"], key=lambda b: abs(math.log(b["variance_ratio"])))
    return f"{b['block']} {b['variance_ratio']:.2f}"


def print_table(folder, intro, describe):
    """One row per method, one column per case: describe(result), or n/a where the case's
    output is missing or empty."""
    print(intro)
    print("| system | method | " + " | ".join(CASES) + " |")
    print("|---|---|" + "---|" * len(CASES))
    for system, methods in SYSTEMS:
        for m in methods:
            rs = [load(folder, m, c) for c in CASES]
            print(f"| {system} | `{m}` | " +
                  " | ".join(describe(r) if r else "n/a" for r in rs) + " |")


def main(folder):
    print_table(folder, "NEES mean over the trials (15 when consistent) and the verdict (ok, or "
                "**X** when inconsistent at the verdict's 1 % false-alarm rate):\n", cell)
    print_table(folder, "\nThe block furthest off and its variance ratio (sampled / predicted; "
                "below 1 the method predicts too much variance there, above 1 too little):\n",
                worst_block)


if __name__ == "__main__":
    main(sys.argv[1])
