"""Type stub of the `cardan` package: what editors complete and type checkers read (the
docstrings are in the modules). tests/test_stubs.py checks it against the package with mypy's
stubtest."""

import os
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Any, Callable, Dict, Iterable, Iterator, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__all__ = [
    "AnalysisError",
    "Builder",
    "CardanError",
    "Check",
    "Contacts",
    "Dragged",
    "JointSpace",
    "Model",
    "Parameter",
    "Pose",
    "ModelError",
    "Results",
    "SolverError",
    "Table",
    "__version__",
    "constant",
    "expression",
    "grid",
    "harmonic",
    "load",
    "polynomial",
    "ramp",
    "run_case",
    "run_cases",
    "spline",
    "sweep",
    "sweep_serial",
]

__version__: str

_Path = Union[str, "os.PathLike[str]"]
_Analysis = Union[str, Callable[["Model"], "Results"]]
_Outputs = Union[Mapping[str, Callable[["Results"], Any]], Iterable[Callable[["Results"], Any]]]

# --- errors ---------------------------------------------------------------------------------

class CardanError(Exception):
    message: str
    printed: str
    file: Optional[str]
    line: Optional[int]
    column: Optional[int]
    def __init__(
        self,
        message: str,
        printed: Optional[str] = None,
        file: Optional[str] = None,
        line: Optional[int] = None,
        column: Optional[int] = None,
    ) -> None: ...
    @property
    def element(self) -> Optional[str]: ...

class ModelError(CardanError): ...

class AnalysisError(CardanError):
    partial: Optional[Results]
    time: Optional[float]
    equations: List[str]
    def __init__(self, *args: Any, partial: Optional[Results] = None) -> None: ...

class SolverError(AnalysisError): ...

# --- results --------------------------------------------------------------------------------

class Table:
    name: str
    title: str
    columns: List[str]
    names: List[str]
    units: List[str]
    def __init__(self, name: str, title: str, columns: List[str], data: npt.NDArray[np.float64]) -> None: ...
    @property
    def t(self) -> npt.NDArray[np.float64]: ...
    @property
    def values(self) -> npt.NDArray[np.float64]: ...
    def __len__(self) -> int: ...
    def __getitem__(self, column: str) -> npt.NDArray[np.float64]: ...
    def __contains__(self, column: object) -> bool: ...
    def unit(self, column: str) -> str: ...
    def to_csv(self) -> str: ...
    def to_pandas(self) -> Any: ...

class Contacts:
    names: List[str]
    units: Dict[str, str]
    t: npt.NDArray[np.float64]
    shape_1: List[str]
    body_1: List[str]
    shape_2: List[str]
    body_2: List[str]
    def __init__(self, text: str) -> None: ...
    def __len__(self) -> int: ...
    def __getitem__(self, column: str) -> npt.NDArray[np.float64]: ...
    @property
    def columns(self) -> List[str]: ...
    def between(self, a: str, b: str) -> npt.NDArray[np.bool_]: ...
    def to_pandas(self) -> Any: ...

class JointSpace:
    coordinates: List[str]
    t: npt.NDArray[np.float64]
    M: npt.NDArray[np.float64]
    h: npt.NDArray[np.float64]
    jacobians: Dict[str, npt.NDArray[np.float64]]
    def __init__(
        self,
        coordinates: List[str],
        t: npt.NDArray[np.float64],
        M: npt.NDArray[np.float64],
        h: npt.NDArray[np.float64],
        jacobians: Dict[str, npt.NDArray[np.float64]],
    ) -> None: ...

class Results:
    kind: str
    tables: Dict[str, Table]
    run: Dict[str, Any]
    native_seconds: float
    glb: Optional[bytes]
    html: Optional[str]
    files: Dict[str, str]
    def __init__(
        self,
        kind: str,
        tables: Dict[str, Table],
        run: Dict[str, Any],
        native_seconds: float = 0.0,
        glb: Optional[bytes] = None,
        html: Optional[str] = None,
        files: Optional[Dict[str, str]] = None,
    ) -> None: ...
    @property
    def points(self) -> Table: ...
    @property
    def point_velocities(self) -> Table: ...
    @property
    def point_accelerations(self) -> Table: ...
    @property
    def joints(self) -> Table: ...
    @property
    def joint_velocities(self) -> Table: ...
    @property
    def joint_accelerations(self) -> Table: ...
    @property
    def bodies(self) -> Table: ...
    @property
    def body_velocities(self) -> Table: ...
    @property
    def body_accelerations(self) -> Table: ...
    @property
    def reactions(self) -> Table: ...
    @property
    def reactions_local(self) -> Table: ...
    @property
    def driver_efforts(self) -> Table: ...
    @property
    def coupler_efforts(self) -> Table: ...
    @property
    def energy(self) -> Table: ...
    @property
    def constraint_drift(self) -> Table: ...
    @property
    def residual(self) -> Table: ...
    @property
    def stability(self) -> Table: ...
    @property
    def modes(self) -> Table: ...
    @property
    def mode_shapes(self) -> Table: ...
    @property
    def warnings(self) -> List[str]: ...
    def joint_space(self) -> JointSpace: ...
    def contacts(self) -> Contacts: ...
    @property
    def status(self) -> str: ...
    @property
    def t(self) -> npt.NDArray[np.float64]: ...
    def __getitem__(self, name: str) -> Table: ...
    def __getattr__(self, name: str) -> Table: ...
    def __iter__(self) -> Iterator[Table]: ...
    def to_csv(self, directory: _Path) -> List[str]: ...
    def save_report(self, directory: _Path) -> List[str]: ...
    def to_pandas(self, table: Optional[str] = None) -> Any: ...
    def plot(self, table: str, columns: Optional[List[str]] = None, ax: Any = None) -> Any: ...

# --- models ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class Check:
    name: str
    dof: int
    rank: int
    redundant: List[str]
    bodies: List[str]
    joints: List[str]
    drivers: List[str]
    unknowns: int
    joint_equations: int
    equations: int
    @property
    def drivers_needed(self) -> int: ...
    @property
    def fully_driven(self) -> bool: ...

Pose = Dict[str, Tuple[Tuple[float, float, float], Tuple[float, float, float, float]]]

@dataclass(frozen=True)
class Dragged:
    pose: Pose
    reached: float
    stop: Optional[str]
    distance: float

@dataclass(frozen=True)
class Parameter:
    name: str
    value: float
    unit: str
    in_model: float
    written: str

class Model:
    text: str
    path: str
    def __init__(self, text: str, path: Optional[_Path] = None) -> None: ...
    @classmethod
    def from_toml(cls, text: str, path: Optional[_Path] = None) -> Model: ...
    @classmethod
    def load(cls, path: _Path, units: Optional[str] = None, *, base: Optional[str] = None, mimic: Optional[str] = None, limits: Optional[bool] = None, damping: Optional[bool] = None, friction: Optional[bool] = None) -> Model: ...
    def with_parameters(self, **values: Any) -> Model: ...
    def parameters(self) -> Dict[str, Parameter]: ...
    def check(self) -> Check: ...
    def run(self, kind: Optional[str] = None, strict: bool = False, report: bool = False, **options: Any) -> Results: ...
    def kinematics(self, **options: Any) -> Results: ...
    def inverse_dynamics(self, **options: Any) -> Results: ...
    def dynamics(self, **options: Any) -> Results: ...
    def statics(self, **options: Any) -> Results: ...
    def quasi_statics(self, **options: Any) -> Results: ...
    def modal(self, **options: Any) -> Results: ...
    def drag(
        self,
        body: str,
        target: Sequence[float],
        point: Optional[str] = None,
        pose: Optional[Pose] = None,
        time: float = 0.0,
    ) -> Dragged: ...

def load(path: _Path, units: Optional[str] = None, *, base: Optional[str] = None, mimic: Optional[str] = None, limits: Optional[bool] = None, damping: Optional[bool] = None, friction: Optional[bool] = None) -> Model: ...

@dataclass
class Builder:
    name: str
    gravity: Any = None
    description: Optional[str] = None
    _ground: Dict[str, Any] = ...
    _tables: List[Tuple[str, Dict[str, Any]]] = ...
    _analysis: Optional[Dict[str, Any]] = None
    _parameters: Dict[str, Any] = ...
    def parameters(self, **values: Any) -> Builder: ...
    def ground(self, **keys: Any) -> Builder: ...
    def body(self, name: str, **keys: Any) -> Builder: ...
    def joint(self, name: str, type: str, **keys: Any) -> Builder: ...
    def driver(self, name: str, **keys: Any) -> Builder: ...
    def force(self, name: str, type: str, **keys: Any) -> Builder: ...
    def curve(self, name: str, type: str, **keys: Any) -> Builder: ...
    def cam(self, name: str, follower: str, **keys: Any) -> Builder: ...
    def surface(self, name: str, type: str, **keys: Any) -> Builder: ...
    def material(self, name: str, **keys: Any) -> Builder: ...
    def shape(self, name: str, type: str, body: str, material: str, **keys: Any) -> Builder: ...
    def coupler(self, name: str, type: str, **keys: Any) -> Builder: ...
    def limit(self, name: str, joint: str, **keys: Any) -> Builder: ...
    def friction(self, name: str, joint: str, coefficient: Optional[float] = None, **keys: Any) -> Builder: ...
    def analysis(self, kind: str, **keys: Any) -> Builder: ...
    def to_toml(self) -> str: ...
    def build(self) -> Model: ...

def polynomial(coefficients: Any) -> Dict[str, Any]: ...
def harmonic(amplitude: float, frequency: float, phase: float = 0.0, offset: float = 0.0) -> Dict[str, Any]: ...
def constant(value: float) -> Dict[str, Any]: ...
def ramp(t0: float, t1: float, f0: float, f1: float) -> Dict[str, Any]: ...
def spline(times: Any, values: Any) -> Dict[str, Any]: ...
def expression(text: str) -> Dict[str, Any]: ...

# --- sweeps ---------------------------------------------------------------------------------

def grid(**axes: Iterable[Any]) -> List[Dict[str, Any]]: ...
def run_case(
    make_model: Callable[..., Model],
    params: Dict[str, Any],
    analysis: _Analysis,
    outputs: Dict[str, Callable[[Results], Any]],
    options: Mapping[str, Any],
    keep_results: bool,
) -> Dict[str, Any]: ...
def run_cases(
    make_model: Callable[..., Model],
    params: List[Dict[str, Any]],
    analysis: _Analysis,
    outputs: Dict[str, Callable[[Results], Any]],
    options: Mapping[str, Any],
    keep_results: bool,
) -> List[Dict[str, Any]]: ...
def sweep(
    make_model: Callable[..., Model],
    params: Iterable[Mapping[str, Any]],
    analysis: _Analysis = "file",
    outputs: Optional[_Outputs] = None,
    executor: Optional[Executor] = None,
    client: Any = None,
    options: Optional[Mapping[str, Any]] = None,
    keep_results: bool = False,
    as_frame: Optional[bool] = None,
    chunksize: Optional[int] = None,
) -> Any: ...
def sweep_serial(
    make_model: Callable[..., Model],
    params: Iterable[Mapping[str, Any]],
    analysis: _Analysis = "file",
    outputs: Optional[_Outputs] = None,
    options: Optional[Mapping[str, Any]] = None,
    keep_results: bool = False,
    as_frame: Optional[bool] = None,
) -> Any: ...
