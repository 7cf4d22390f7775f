"""imuconv: IMU propagation and preintegration as one computation.

Perturbation (error-state) conventions are plugins; the Registry derives the conversion
Jacobians between any two of them. Arrays are NumPy float64 arrays.

    import imuconv, numpy as np
    reg = imuconv.Registry()
    x = imuconv.State(p=[0, 0, 1], q_wxyz=[1, 0, 0, 0], v=[0.5, 0, 0])
    J = reg.conversion("left", "gtsam_navstate", x)          # (15, 15)
    m = imuconv.preintegrate(reg, samples, bg=np.zeros(3), ba=np.zeros(3), noise=noise,
                             propagator="euler")
    g = m.express(reg, "gtsam_manifold")                      # g.delta_R, g.J_bias, g.cov, g.blocks

Errors of the library raise imuconv.Error (a RuntimeError) with the library's message; bad
arguments raise ValueError naming the argument.
"""

from ._imuconv import (  # noqa: F401
    Error,
    Expressed,
    Increment,
    Preintegrated,
    Propagation,
    Registry,
    Residual,
    State,
    bias_corrected_delta,
    check,
    from_convention,
    preintegrate,
    propagate,
    propagate_by_preintegration,
    residual,
    run,
    write_measurements,
)

try:  # built only with Ceres (imuconv::ceres)
    from ._imuconv import optimize  # noqa: F401
except ImportError:  # pragma: no cover
    pass

try:
    from ._imuconv import __version__  # noqa: F401
except ImportError:  # pragma: no cover
    __version__ = "unknown"


__all__ = [
    "Error", "Expressed", "Increment", "Preintegrated", "Propagation", "Registry", "Residual", "State",
    "bias_corrected_delta", "check", "from_convention", "preintegrate", "propagate", "propagate_by_preintegration",
    "residual", "run", "write_measurements",
]
