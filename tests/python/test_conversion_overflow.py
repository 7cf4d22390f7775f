# A conversion whose result overflows raises in the Python module instead of returning inf, as
# `imuconv convert` exits 2 and a run refuses a non-finite output. Each input is finite and
# passes every check; only the product overflows.
import numpy as np
import pytest

import imuconv

HOVER_Q = [0.42294713118151406, 0.547875169929263, -0.5992581858662474, 0.40229112477483586]


def state_at(x):
    return imuconv.State(p=[x, x, x], q_wxyz=HOVER_Q)


def test_an_overflowing_covariance_raises(reg):
    # J holds the position (1e200): J S J^T squares it, past DBL_MAX (1.8e308).
    with pytest.raises(ValueError, match=r"convert_covariance: produced a non-finite number \(result\)"):
        reg.convert_covariance("left", "right_invariant_se23", state_at(1e200), np.eye(15))


def test_an_overflowing_transition_raises(reg):
    # J_e holds the end position (1e200), Phi entries of 1e200: their product overflows.
    with pytest.raises(ValueError, match=r"convert_transition: produced a non-finite number \(result\)"):
        reg.convert_transition("left", "right_invariant_se23", state_at(0.0), state_at(1e200), 1e200 * np.eye(15))


def test_an_overflowing_jacobian_raises(reg):
    # The body-frame chart rotates the world position: R^T p sums components of 1.7e308.
    with pytest.raises(ValueError, match=r"conversion: produced a non-finite number \(result\)"):
        reg.conversion("right_invariant_se23", "gtsam_navstate", state_at(1.7e308))


def test_a_far_but_finite_conversion_is_returned(reg):
    # 1e100 m: J S J^T of about 1e200, below DBL_MAX.
    assert np.isfinite(reg.convert_covariance("left", "right_invariant_se23", state_at(1e100), np.eye(15))).all()
