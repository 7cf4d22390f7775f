#!/usr/bin/env python3
"""Derives the small example inputs from the files next to this script (see SOURCE.md).

  generic_imu_seconds.csv  the first 2.0 s of V1_01_easy_imu0_slice.csv, re-written as a generic
                           CSV: ';'-separated, absolute time in seconds (all 9 decimals kept, so
                           no precision is lost), columns reordered to time;ax;ay;az;gx;gy;gz.
  gtsam_smooth0_manifold.measurements.json
                           GTSAM's ManifoldPreintegration output for the reference case smooth-0
                           (tests/data/reference/gtsam/smooth-0.gtsam.json, "zoh"/"manifold"),
                           in the imuconv measurements format: what a user would dump from GTSAM.
Run from anywhere: python3 examples/data/derive.py
"""
import json
import os

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.normpath(os.path.join(here, "..", ".."))

# ---- generic CSV ----
with open(os.path.join(here, "V1_01_easy_imu0_slice.csv")) as f:
    lines = [l.rstrip("\r\n") for l in f]
rows = [l.split(",") for l in lines[1:]]
t0 = int(rows[0][0])
out = ["time;ax;ay;az;gx;gy;gz"]
for r in rows:
    ns = int(r[0])
    if ns - t0 > 2_000_000_000:
        break
    secs = "%d.%09d" % (ns // 1_000_000_000, ns % 1_000_000_000)
    out.append(";".join([secs, r[4], r[5], r[6], r[1], r[2], r[3]]))
with open(os.path.join(here, "generic_imu_seconds.csv"), "w") as f:
    f.write("\n".join(out) + "\n")

# ---- a GTSAM dump ----
case = json.load(open(os.path.join(root, "tests/data/reference/cases/smooth-0.json")))
ref = json.load(open(os.path.join(root, "tests/data/reference/gtsam/smooth-0.gtsam.json")))
m = ref["zoh"]["manifold"]
t_start = case["imu"][0][0]
t_end = case["imu"][-1][0]
doc = {
    "description": "GTSAM 4.3a0 PreintegratedCombinedMeasurements (ManifoldPreintegration, zero-order hold) for the "
                   "reference case smooth-0; J_bias columns [ba, bg] as GTSAM orders them, cov15 in [theta, p, v, ba, bg].",
    "measurements": [{
        "t_start": t_start,
        "t_end": t_end,
        "dt": m["deltaT"],
        "bias_estimate": {"bg": case["state_s"]["bg"], "ba": case["state_s"]["ba"]},
        "delta": {"R": m["deltaR"], "dp": m["deltaP"], "dv": m["deltaV"]},
        "J_bias": {"matrix": m["J_bias"]},
        "cov": {"convention": "gtsam_manifold", "blocks": ["theta", "p", "v", "ba", "bg"], "matrix": m["cov15"]},
    }],
}
with open(os.path.join(here, "gtsam_smooth0_manifold.measurements.json"), "w") as f:
    json.dump(doc, f, indent=1)
    f.write("\n")
