#!/usr/bin/env python3
"""Reproduce one of GTSAM's reference cases from Python, and convert its covariance.

    PYTHONPATH=build/python python3 examples/python/reproduce_gtsam_case.py [CASE_ID]

Preintegrates the case's IMU samples twice, by propagation with the zero-order-hold `euler`
propagator (the note, section 3.1) and with the native `manifold` scheme, expresses both in
GTSAM's manifold convention, and prints the note's entrywise difference d against what GTSAM
itself computed (tests/data/reference/gtsam/). Then it propagates the case's start state by
the measurement and shows the same end covariance in GTSAM's NavState chart and OpenVINS's.
"""
import json
import pathlib
import sys

import numpy as np

import imuconv

DATA = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "reference"


def paper_d(reference, estimate):
    """max over entries of |r - e| / |r| where |r| > 1e-4, else |r - e| (FORMAT.md)."""
    r, e = np.asarray(reference, float), np.asarray(estimate, float)
    big = np.abs(r) > 1e-4
    return float(np.where(big, np.abs(r - e) / np.where(big, np.abs(r), 1.0), np.abs(r - e)).max())


def main(case_id):
    case = json.loads((DATA / "cases" / f"{case_id}.json").read_text())
    gtsam = json.loads((DATA / "gtsam" / f"{case_id}.gtsam.json").read_text())["zoh"]["manifold"]
    reg = imuconv.Registry()
    samples = np.array(case["imu"])  # (N, 7): t, wx, wy, wz, ax, ay, az
    s = case["state_s"]

    print(f"{case_id}: {len(samples)} samples, {samples[-1, 0] - samples[0, 0]:.3f} s")
    print(f"{'method':<28}{'deltaR':>10}{'deltaP':>10}{'deltaV':>10}{'J_bias':>10}{'cov15':>10}")
    for label, method in [("propagator=euler", dict(propagator="euler")),
                          ("preintegrator=manifold", dict(preintegrator="manifold"))]:
        m = imuconv.preintegrate(reg, samples, bg=s["bg"], ba=s["ba"], noise=case["noise"], **method)
        g = m.express(reg, "gtsam_manifold")  # blocks [theta, p, v, ba, bg], as GTSAM's cov15
        row = [paper_d(gtsam[k], v) for k, v in
               [("deltaR", g.delta_R), ("deltaP", g.dp), ("deltaV", g.dv), ("J_bias", g.J_bias), ("cov15", g.cov)]]
        print(f"{label:<28}" + "".join(f"{d:>10.1e}" for d in row))

    x_s = imuconv.State(p=s["p"], q_wxyz=s["q_wxyz"], v=s["v"], bg=s["bg"], ba=s["ba"])
    cov_left = np.array(case["cov_s_left"]["matrix"])  # left error state, blocks [p, theta, v, bg, ba]
    cov_nav = reg.convert_covariance("left", "gtsam_navstate", x_s, cov_left)
    m = imuconv.preintegrate(reg, samples, bg=s["bg"], ba=s["ba"], noise=case["noise"], propagator="rk4")
    e = imuconv.propagate_by_preintegration(reg, m, x_s, cov_nav, "gtsam_navstate", gravity=case["gravity"])
    cov_ov = reg.convert_covariance("gtsam_navstate", "openvins_jpl", e.x_e, e.cov)
    print(f"\nend state p = {np.array2string(e.x_e.p, precision=4)}, q_wxyz = {np.array2string(e.x_e.q_wxyz, precision=4)}")
    for conv, cov in [("gtsam_navstate", e.cov), ("openvins_jpl", cov_ov)]:
        blocks = reg.blocks("state_convention", conv)
        sigmas = np.sqrt(np.diag(cov)).reshape(5, 3)
        print(f"{conv:<16}" + "  ".join(f"{b}: {np.array2string(sd, precision=3)}" for b, sd in zip(blocks, sigmas)))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "smooth-0")
