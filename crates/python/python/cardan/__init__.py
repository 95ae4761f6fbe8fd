"""cardan: kinematic and dynamic analysis of spatial mechanisms in absolute coordinates with
Euler parameters (Nikravesh, Haug), from Python.

>>> import cardan
>>> model = cardan.load("examples/slider_crank_inverse.toml")
>>> model.check().dof
1
>>> results = model.inverse_dynamics()
>>> torque = results.driver_efforts["motor.torque"]          # numpy float64, one value per time

Results are numpy arrays with named columns and units (:class:`Table`); ``to_csv`` writes the
``cardan run`` files byte for byte, ``to_pandas`` gives DataFrames. Design sweeps run on a
process pool or a Dask cluster: :func:`sweep`, :func:`grid`. See docs/python.md.
"""

from ._cardan import __version__
from ._errors import AnalysisError, CardanError, ModelError, SolverError
from ._model import Builder, Check, Dragged, Model, Parameter, Pose, constant, expression, harmonic, load, polynomial, ramp, spline
from ._results import Contacts, JointSpace, Results, Table
from ._sweep import grid, run_case, run_cases, sweep, sweep_serial

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
