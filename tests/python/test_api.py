# The module's API: conversions against central differences of the conventions' own charts
# (through the module's retract/local, so a transposed or reordered array at the binding
# would show), round trips, the measurement's way into a convention and back, and the
# errors a caller gets for bad input.
import itertools
import warnings

import numpy as np
import pytest

import imuconv
from conftest import load_case, start_state


def sample_state():
    rng = np.random.default_rng(7)
    q = rng.normal(size=4)
    return imuconv.State(p=rng.normal(size=3), q_wxyz=q / np.linalg.norm(q), v=rng.normal(size=3),
                         bg=0.01 * rng.normal(size=3), ba=0.1 * rng.normal(size=3))


def central_conversion(reg, a, b, x, h=1e-6):
    """d local_b(x, retract_a(x, d)) / d d at 0, column by column."""
    J = np.zeros((15, 15))
    for i in range(15):
        e = np.zeros(15)
        e[i] = h
        J[:, i] = (reg.local(b, x, reg.retract(a, x, e)) - reg.local(b, x, reg.retract(a, x, -e))) / (2 * h)
    return J


def test_plugins_are_listed(reg):
    plugins = reg.plugins()
    kinds = {p["kind"] for p in plugins}
    assert kinds == {"state_convention", "preint_convention", "propagator", "preintegrator", "residual"}
    for p in plugins:
        assert set(p) >= {"id", "kind", "file", "version", "blocks"}
        if p["kind"] in ("state_convention", "preint_convention"):
            assert sorted(p["blocks"]) == ["ba", "bg", "p", "theta", "v"]
    assert {"euler", "rk4", "midpoint"} <= set(reg.ids("propagator"))
    # the systems' own IMU factors (plugins/residuals/), by the kind's name
    assert {"vins_fusion", "basalt", "okvis2", "orb_slam3"} <= set(reg.ids("residual"))
    assert reg.load_issues == []


def test_state_conversions_match_central_differences(reg):
    """Every ordered pair of state conventions: the registry's conversion against central
    differences (h = 1e-6) of the charts. The truncation error is O(h^2 |d3|) ~ 1e-12 and the
    rounding O(eps / h) ~ 1e-10 on entries of order one, so 1e-7 absolute (on a state whose
    entries are of order one) leaves room without hiding a wrong block, which is O(1)."""
    x = sample_state()
    ids = reg.ids("state_convention")
    assert len(ids) >= 7
    for a, b in itertools.product(ids, ids):
        J = reg.conversion(a, b, x)
        assert J.shape == (15, 15)
        np.testing.assert_allclose(J, central_conversion(reg, a, b, x), atol=1e-7, err_msg=f"{a} -> {b}")


def test_conversion_round_trips_and_covariance(reg):
    """conversion(b, a) conversion(a, b) = I to rounding (1e-9: the product of two
    well-conditioned 15x15 Jacobians of order-one entries), and convert_covariance is J S J^T."""
    x = sample_state()
    rng = np.random.default_rng(3)
    A = rng.normal(size=(15, 15))
    S = A @ A.T
    for a, b in itertools.product(reg.ids("state_convention"), repeat=2):
        Jab = reg.conversion(a, b, x)
        np.testing.assert_allclose(reg.conversion(b, a, x) @ Jab, np.eye(15), atol=1e-9, err_msg=f"{a} <-> {b}")
        np.testing.assert_allclose(reg.convert_covariance(a, b, x, S), Jab @ S @ Jab.T, rtol=1e-12, atol=1e-12)


def test_increment_conversions_match_central_differences(reg):
    case, _ = load_case("aggressive-1")
    s = case["state_s"]
    m = imuconv.preintegrate(reg, np.array(case["imu"]), bg=s["bg"], ba=s["ba"], noise=case["noise"],
                             propagator="rk4")
    d = m.delta
    h = 1e-6
    for a, b in itertools.product(reg.ids("preint_convention"), repeat=2):
        J = reg.increment_conversion(a, b, d)
        Jn = np.zeros((15, 15))
        for i in range(15):
            e = np.zeros(15)
            e[i] = h
            Jn[:, i] = (reg.increment_local(b, d, reg.increment_retract(a, d, e)) -
                        reg.increment_local(b, d, reg.increment_retract(a, d, -e))) / (2 * h)
        # The increment of a 10 s aggressive case has |dp| ~ 1e2: rounding eps |dp| / h ~ 2e-8.
        np.testing.assert_allclose(J, Jn, atol=1e-6, err_msg=f"{a} -> {b}")


def test_express_and_import_round_trip(reg):
    """A measurement expressed in each increment convention and imported back (from_convention)
    is the same measurement: cov and J_bias to 1e-12 relative to their scale (two conversions
    and their inverses, each exact to rounding)."""
    case, _ = load_case("smooth-2")
    s = case["state_s"]
    m = imuconv.preintegrate(reg, np.array(case["imu"]), bg=s["bg"], ba=s["ba"], noise=case["noise"],
                             propagator="midpoint")
    for conv in reg.ids("preint_convention"):
        g = m.express(reg, conv)
        assert g.convention == conv
        assert g.blocks == reg.blocks("preint_convention", conv)
        back = imuconv.from_convention(reg, conv, dt=g.dt, delta=g.delta, bg_hat=g.bg_hat, ba_hat=g.ba_hat,
                                       J_bias=g.J_bias, cov=g.cov, jacobian_convention=g.jacobian_convention)
        for name in ["cov", "J_bias"]:
            ref, got = getattr(m, name), getattr(back, name)
            assert np.abs(ref - got).max() <= 1e-12 * np.abs(ref).max(), (conv, name)
        np.testing.assert_allclose(back.delta.dR, m.delta.dR, atol=1e-14)
        back2 = g.to_preintegrated(reg)
        np.testing.assert_array_equal(back2.cov, back.cov)


def test_state_accessors():
    x = imuconv.State(p=[1, 2, 3], q_GtoI_xyzw=[0, 0, np.sin(0.25), np.cos(0.25)])
    np.testing.assert_allclose(x.q_wxyz, [np.cos(0.25), 0, 0, np.sin(0.25)], atol=1e-15)
    assert x.R.shape == (3, 3) and x.p.shape == (3,)
    np.testing.assert_array_equal(x.v, np.zeros(3))
    x.v = [4, 5, 6]
    np.testing.assert_array_equal(x.v, [4, 5, 6])
    y = imuconv.State(R=x.R, p=x.p)
    np.testing.assert_array_equal(y.R, x.R)


def test_bad_input_is_a_clear_error(reg):
    case, _ = load_case("smooth-0")
    samples = np.array(case["imu"])
    noise = case["noise"]
    zero = np.zeros(3)
    x = sample_state()
    m = imuconv.preintegrate(reg, samples, bg=zero, ba=zero, noise=noise, propagator="euler")
    cases = [
        (lambda: imuconv.State(q_wxyz=[1, 0, 0, 0.1]), ValueError, "q_wxyz: not a unit quaternion"),
        (lambda: imuconv.State(p=[0, 0], q_wxyz=[1, 0, 0, 0]), ValueError, r"p: expected shape \(3,\), got \(2,\)"),
        (lambda: imuconv.State(), ValueError, "exactly one of q_wxyz, R and q_GtoI_xyzw"),
        (lambda: imuconv.State(R=2 * np.eye(3)), ValueError, "R: not a rotation matrix"),
        (lambda: reg.conversion("left", "no_such_convention", x), imuconv.Error, "no_such_convention"),
        (lambda: reg.convert_covariance("left", "gtsam_navstate", x, -np.eye(15)), ValueError,
         "S: not a valid covariance"),
        (lambda: reg.convert_covariance("left", "gtsam_navstate", x, np.eye(9)), ValueError,
         r"S: expected shape \(15, 15\), got \(9, 9\)"),
        (lambda: imuconv.preintegrate(reg, samples, bg=zero, ba=zero, noise=noise), ValueError,
         "exactly one of propagator="),
        (lambda: imuconv.preintegrate(reg, samples, bg=zero, ba=zero, noise=noise, propagator="nope"),
         imuconv.Error, "nope"),
        (lambda: imuconv.preintegrate(reg, samples[:, :6], bg=zero, ba=zero, noise=noise, propagator="euler"),
         ValueError, r"samples: expected shape \(N, 7\)"),
        (lambda: imuconv.preintegrate(reg, samples[::-1], bg=zero, ba=zero, noise=noise, propagator="euler"),
         ValueError, "samples: row 1: time must increase strictly"),
        (lambda: imuconv.preintegrate(reg, np.where(np.arange(7) == 3, np.nan, samples), bg=zero, ba=zero,
                                      noise=noise, propagator="euler"), ValueError, "samples: row 0: wz is not finite"),
        (lambda: imuconv.preintegrate(reg, samples, bg=zero, ba=zero, noise={"gyro_noise_density": 1},
                                      propagator="euler"), ValueError, "noise: missing 'accel_noise_density'"),
        (lambda: imuconv.preintegrate(reg, samples, bg=zero, ba=zero, noise=dict(noise, typo=1.0),
                                      propagator="euler"), ValueError, "noise: unknown key 'typo'"),
        (lambda: imuconv.preintegrate(reg, samples, bg=zero, ba=zero, noise=noise, propagator="euler",
                                      t_end=samples[-1, 0] + 1), ValueError, "samples: no window"),
        (lambda: imuconv.residual(reg, "ceres", m, x, x, "left"), ValueError, "unknown residual kind 'ceres'"),
    ]
    for call, error, message in cases:
        with pytest.raises(error, match=message):
            call()


def test_unreadable_plugin_directory_is_reported(tmp_path):
    bad = tmp_path / "imuconv_plugin_bad.so"
    bad.write_bytes(b"not an ELF file")
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        r = imuconv.Registry([str(tmp_path)])
    assert len(r.load_issues) == 1 and "imuconv_plugin_bad.so" in r.load_issues[0]["file"]
    assert any("imuconv_plugin_bad.so" in str(x.message) for x in w)
    assert "euler" in r.ids("propagator")  # the rest loaded
