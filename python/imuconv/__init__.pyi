# Type stubs of the imuconv module (python/src/*.cpp). Arrays are float64 NumPy arrays;
# array arguments accept anything NumPy converts (lists included) of the stated shape.
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike
Array = npt.NDArray[np.float64]

__version__: str

class Error(RuntimeError): ...

class State:
    def __init__(self, *, p: Optional[ArrayLike] = ..., q_wxyz: Optional[ArrayLike] = ..., v: Optional[ArrayLike] = ...,
                 bg: Optional[ArrayLike] = ..., ba: Optional[ArrayLike] = ..., R: Optional[ArrayLike] = ...,
                 q_GtoI_xyzw: Optional[ArrayLike] = ...) -> None: ...
    R: Array  # (3, 3) body to world
    @property
    def q_wxyz(self) -> Array: ...  # (4,) Hamilton, w >= 0
    p: Array  # (3,)
    v: Array  # (3,)
    bg: Array  # (3,)
    ba: Array  # (3,)

class Increment:
    def __init__(self, *, dR: Optional[ArrayLike] = ..., q_wxyz: Optional[ArrayLike] = ..., dp: Optional[ArrayLike] = ...,
                 dv: Optional[ArrayLike] = ...) -> None: ...
    dR: Array  # (3, 3)
    @property
    def q_wxyz(self) -> Array: ...
    dp: Array
    dv: Array
    dbg: Array
    dba: Array

class Registry:
    def __init__(self, plugin_dirs: Sequence[str] = ..., *, allow_override: bool = ...) -> None: ...
    @property
    def load_issues(self) -> List[Dict[str, Any]]: ...
    def plugins(self) -> List[Dict[str, Any]]: ...
    def ids(self, kind: str) -> List[str]: ...
    def info(self, kind: str, id: str) -> Dict[str, Any]: ...
    def blocks(self, kind: str, id: str) -> List[str]: ...
    @staticmethod
    def search_path(plugin_dirs: Sequence[str] = ...) -> List[str]: ...
    def conversion(self, from_convention: str, to_convention: str, x: State) -> Array: ...  # (15, 15)
    def convert_covariance(self, from_convention: str, to_convention: str, x: State, S: ArrayLike) -> Array: ...
    def convert_transition(self, from_convention: str, to_convention: str, x_s: State, x_e: State,
                           Phi: ArrayLike) -> Array: ...
    def retract(self, convention: str, x: State, d: ArrayLike) -> State: ...
    def local(self, convention: str, x: State, y: State) -> Array: ...  # (15,)
    def increment_conversion(self, from_convention: str, to_convention: str, delta: Increment) -> Array: ...
    def increment_retract(self, convention: str, delta: Increment, d: ArrayLike) -> Increment: ...
    def increment_local(self, convention: str, delta: Increment, other: Increment) -> Array: ...

class Expressed:
    convention: str
    jacobian_convention: str
    blocks: List[str]
    J_bias_rows: List[str]  # J_bias's row blocks, jacobian_convention's order
    J_bias_columns: List[str]  # J_bias's column blocks, e.g. ['bg', 'ba'] or ['ba', 'bg']
    dt: float
    delta: Increment
    @property
    def delta_R(self) -> Array: ...  # (3, 3)
    @property
    def q_wxyz(self) -> Array: ...
    @property
    def dp(self) -> Array: ...
    @property
    def dv(self) -> Array: ...
    @property
    def bg_hat(self) -> Array: ...
    @property
    def ba_hat(self) -> Array: ...
    @property
    def J_bias(self) -> Array: ...  # (9, 6)
    @property
    def cov(self) -> Array: ...  # (15, 15)
    def to_preintegrated(self, reg: Registry) -> Preintegrated: ...

class Preintegrated:
    dt: float
    delta: Increment
    @property
    def bg_hat(self) -> Array: ...
    @property
    def ba_hat(self) -> Array: ...
    @property
    def J_bias(self) -> Array: ...  # (9, 6), rows preint_reference (theta, p, v), columns [bg, ba]
    @property
    def cov(self) -> Array: ...  # (15, 15) preint_reference
    def express(self, reg: Registry, convention: str) -> Expressed: ...

class Propagation:
    x_e: State
    @property
    def Phi(self) -> Array: ...
    @property
    def cov(self) -> Array: ...

class Residual:
    @property
    def r(self) -> Array: ...
    @property
    def H_start(self) -> Array: ...
    @property
    def H_end(self) -> Array: ...
    @property
    def cov(self) -> Array: ...
    @property
    def H_increment(self) -> Array: ...

Noise = Dict[str, float]  # gyro_noise_density, accel_noise_density, gyro_random_walk, accel_random_walk

def preintegrate(reg: Registry, samples: ArrayLike, *, bg: ArrayLike, ba: ArrayLike, noise: Noise,
                 propagator: Optional[str] = ..., preintegrator: Optional[str] = ..., t_start: Optional[float] = ...,
                 t_end: Optional[float] = ..., allow_gaps: bool = ...) -> Preintegrated: ...
def from_convention(reg: Registry, convention: str, *, dt: float, delta: Increment, bg_hat: ArrayLike,
                    ba_hat: ArrayLike, J_bias: ArrayLike, cov: ArrayLike,
                    jacobian_convention: Optional[str] = ...) -> Preintegrated: ...
def propagate(reg: Registry, propagator: str, convention: str, x: State, cov: ArrayLike, samples: ArrayLike, *,
              noise: Noise, gravity: ArrayLike = ..., t_start: Optional[float] = ...,
              t_end: Optional[float] = ..., allow_gaps: bool = ...) -> Propagation: ...
def propagate_by_preintegration(reg: Registry, m: Preintegrated, x_s: State, cov_s: ArrayLike, convention: str, *,
                                gravity: ArrayLike = ...) -> Propagation: ...
def residual(reg: Registry, kind: str, m: Preintegrated, x_s: State, x_e: State, convention: str, *,
             gravity: ArrayLike = ...) -> Residual: ...
def bias_corrected_delta(reg: Registry, m: Preintegrated, jacobian_convention: str, *, bg: ArrayLike,
                         ba: ArrayLike) -> Increment: ...
# A path: str, bytes or os.PathLike giving either (os.fsencode).
_Path = Union[str, bytes, os.PathLike[str], os.PathLike[bytes]]
def run(pipeline: _Path, *, plugin_dirs: Sequence[str] = ..., threads: int = ...) -> Dict[str, Any]: ...
MeasurementValues = Union[Preintegrated, Expressed, Sequence[Union[Preintegrated, Expressed]]]
def check(reg: Registry, measurements: Union[_Path, Mapping[str, Any], Sequence[Mapping[str, Any]],
                                             MeasurementValues], *,
          case: Optional[_Path] = ..., samples: Optional[ArrayLike] = ...,
          noise: Optional[Noise] = ..., t_start: Optional[Union[float, Sequence[float]]] = ...) -> Dict[str, Any]: ...
def write_measurements(path: _Path, reg: Registry, measurements: MeasurementValues, *,
                       t_start: Optional[Union[float, Sequence[float]]] = ...,
                       conventions: Sequence[str] = ...) -> None: ...
# Only when the module was built with Ceres (imuconv::ceres).
def optimize(reg: Registry, samples: ArrayLike, poses: ArrayLike, *, noise: Noise, keyframe_step: float,
             method: str = ..., convention: str = ..., pose_sigma: Tuple[float, float] = ...,
             residual: str = ..., gravity: ArrayLike = ..., reintegrate_gyro: float = ...,
             reintegrate_accel: float = ..., max_rounds: int = ...) -> Dict[str, Any]: ...
