"""Models: a model file's text (TOML, ``docs/model-format.md``) and the analyses run on it."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple

from . import _cardan
from ._errors import raise_error
from ._results import Results


@dataclass(frozen=True)
class Check:
    """What ``cardan check`` finds: the degrees of freedom of the joints alone (``dof``), the
    rank of their Jacobian, the redundant joint equations by name, and the element counts.
    ``drivers_needed`` is the number of drivers a kinematic analysis needs (= ``dof``)."""

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
    def drivers_needed(self) -> int:
        """Drivers a kinematic analysis needs: one per degree of freedom."""
        return self.dof

    @property
    def fully_driven(self) -> bool:
        """Whether the drivers fix every degree of freedom (a kinematic analysis can run)."""
        return len(self.drivers) == self.dof


Pose = Dict[str, Tuple[Tuple[float, float, float], Tuple[float, float, float, float]]]
"""Body name → (position of the centre of mass in model units, Euler parameters e0..e3)."""


@dataclass(frozen=True)
class Dragged:
    """The outcome of :meth:`Model.drag`: the new ``pose``, the fraction of the step taken
    (``reached``, 1.0 unless a stop or a failed solve cut it back), what cut it back (``stop``:
    the limit's name, ``"not converged"``, or None) and the dragged point's ``distance`` to the
    target (model units; about 1e-3 of the motion it took, the drag's soft pull)."""

    pose: Pose
    reached: float
    stop: Optional[str]
    distance: float


@dataclass(frozen=True)
class Parameter:
    """One of a model's ``[parameters]`` (:meth:`Model.parameters`)."""

    name: str
    #: Its value in SI units (a plain number as written).
    value: float
    #: Its SI unit ("m", "kg m^2", "1/s"; "" for a plain or dimensionless number).
    unit: str
    #: The number the model uses: the value in the model's units (mm for a length in a mm model).
    in_model: float
    #: Its definition as written in the file.
    written: str


def _parameter_text(v: Any) -> str:
    """A value of ``with_parameters`` as the text ``--set`` takes."""
    if hasattr(v, "item"):  # numpy scalars
        v = v.item()
    if isinstance(v, bool) or not isinstance(v, (int, float, str)):
        raise TypeError(f"a parameter's value is a number or a string such as \"90 mm\", not {type(v).__name__}")
    return v if isinstance(v, str) else repr(v)


def _prepared(out: Dict[str, Any]) -> Any:
    """The native handle of a prepared model text (``_cardan.prepare``'s dict); raises its
    :class:`ModelError`."""
    if out["error"] is not None:
        raise_error(out["error"])
    return out["model"]


class Model:
    """A mechanism model: the text of a model file and the path it came from (which names it
    in error messages and anchors the files it refers to).

    Models are cheap, immutable and picklable (they travel to process pools and Dask workers
    as their text). Each analysis method runs the whole analysis in Rust with the GIL
    released; Ctrl-C stops it at its next step and raises ``KeyboardInterrupt`` with the
    results so far as its ``partial`` attribute."""

    def __init__(self, text: str, path: "os.PathLike[str] | str | None" = None) -> None:
        """The model of model-file ``text``, validated at once (names, numbers, shapes: what
        ``cardan check`` reads before it assembles); a bad model raises :class:`ModelError`
        here, with its file, line and column. ``path`` names it in messages and anchors the
        files it refers to (``"<model>"`` when not given)."""
        self.text = text
        self.path = os.fspath(path) if path is not None else "<model>"
        self._native = _prepared(_cardan.prepare(self.text, self.path))

    @classmethod
    def _trusted(cls, text: str, path: str, native: Any = None) -> "Model":
        """A model whose text was validated before (unpickling, an import), with the native
        handle of its prepared text if there is one (not after unpickling: the text is prepared
        again by each call then)."""
        model = cls.__new__(cls)
        model.text, model.path, model._native = text, path, native
        return model

    @classmethod
    def from_toml(cls, text: str, path: "os.PathLike[str] | str | None" = None) -> "Model":
        """A model from model-file text, validated at once (a bad model raises
        :class:`ModelError` here). ``path`` (optional) names it in messages; without it the
        model is ``<string>`` and relative file references are taken from the current
        directory."""
        return cls(text, path if path is not None else "<string>")

    @classmethod
    def load(
        cls,
        path: "os.PathLike[str] | str",
        units: "str | None" = None,
        *,
        base: "str | None" = None,
        mimic: "str | None" = None,
        limits: "bool | None" = None,
        damping: "bool | None" = None,
        friction: "bool | None" = None,
    ) -> "Model":
        """Reads and validates a model file (a ``str`` or a ``pathlib.Path``): see :func:`load`."""
        return load(path, units, base=base, mimic=mimic, limits=limits, damping=damping, friction=friction)

    def with_parameters(self, **values: Any) -> "Model":
        """This model with ``[parameters]`` given values, as ``cardan run --set`` gives them:
        ``model.with_parameters(crank=0.1, speed="120 rpm")``. A number is in the model's
        units of the parameter (metres for a length in an SI model), a string is an expression
        with units (``"90 mm"``); another unit than the file's, or a name the file does not
        define, raises :class:`ModelError`. The new model's text has those definitions
        replaced (``crank = "0.1 m"``)."""
        pairs = [(name, _parameter_text(v)) for name, v in values.items()]
        out = _cardan.with_parameters(self.text, self.path, pairs)
        if out["error"] is not None:
            raise_error(out["error"])
        return Model(out["text"], self.path)

    def parameters(self) -> Dict[str, Parameter]:
        """The model's ``[parameters]``, evaluated: name → :class:`Parameter` (its SI value and
        unit, the number the model uses in its own units, the text as written)."""
        out = _cardan.parameters(self.text, self.path)
        if out["error"] is not None:
            raise_error(out["error"])
        return {
            name: Parameter(name=name, value=value, unit=unit, in_model=in_model, written=written)
            for name, value, unit, in_model, written in out["parameters"]
        }

    def check(self) -> Check:
        """Validates the model and analyses its joints: raises :class:`ModelError` for a bad
        model, :class:`AnalysisError` when it cannot be assembled."""
        out = _cardan.check(self.text, self.path, self._native)
        if out["error"] is not None:
            raise_error(out["error"])
        return Check(
            name=out["name"],
            dof=out["dof"],
            rank=out["rank"],
            redundant=list(out["redundant"]),
            bodies=list(out["bodies"]),
            joints=list(out["joints"]),
            drivers=list(out["drivers"]),
            unknowns=out["unknowns"],
            joint_equations=out["joint_equations"],
            equations=out["equations"],
        )

    def run(self, kind: Optional[str] = None, strict: bool = False, report: bool = False, **options: Any) -> Results:
        """Runs the analysis of the model file's ``[analysis]`` table, with ``kind``
        (``"kinematic"``, ``"inverse_dynamics"`` or ``"dynamic"``) and any ``[analysis]`` keys
        given here set over the file's (``t_end=2.0, steps=400, outputs={"points": [...]}``;
        switching the kind drops the file's keys the new kind does not take).

        ``strict=True`` turns warnings about doubtful results into an :class:`AnalysisError`
        (with the complete results as ``partial``). ``report=True`` also makes the 3D
        animation and the report page of ``cardan run`` (``Results.glb``, ``Results.html``;
        shown inline in Jupyter, saved by :meth:`Results.save_report`)."""
        out = _cardan.run(self.text, self.path, kind, options or None, strict, report, self._native)
        results = Results._from_native(out) if out["tables"] else None
        if out["interrupted"]:
            err = KeyboardInterrupt("cardan: analysis stopped by Ctrl-C; its results so far are in .partial")
            err.partial = results  # type: ignore[attr-defined]
            raise err
        if out["error"] is not None:
            raise_error(out["error"], partial=results)
        assert results is not None
        return results

    def kinematics(self, **options: Any) -> Results:
        """A kinematic analysis: positions, velocities, accelerations of the driven motion."""
        return self.run("kinematic", **options)

    def inverse_dynamics(self, **options: Any) -> Results:
        """Inverse dynamics: the driver efforts (motor torques and forces) and joint reactions
        along the driven motion."""
        return self.run("inverse_dynamics", **options)

    def dynamics(self, **options: Any) -> Results:
        """Forward dynamics: the motion under forces, from the assembled state."""
        return self.run("dynamic", **options)

    def statics(self, **options: Any) -> Results:
        """The static equilibrium under the loads, drivers held at their value at ``time``:
        pose, holding efforts, reactions and stability."""
        return self.run("static", **options)

    def quasi_statics(self, **options: Any) -> Results:
        """The equilibrium at each output time, drivers following their functions."""
        return self.run("quasi_static", **options)

    def modal(self, **options: Any) -> Results:
        """Vibration modes about the equilibrium: ``results.modes`` (frequencies, damping),
        ``results.mode_shapes``, and the linearized model's matrices in ``results.files``."""
        return self.run("modal", **options)

    def drag(
        self,
        body: str,
        target: Sequence[float],
        point: Optional[str] = None,
        pose: Optional["Pose"] = None,
        time: float = 0.0,
    ) -> "Dragged":
        """One drag step, FreeCAD's interaction: the point ``point`` of ``body`` (a named point;
        its centre of mass without one) is pulled toward ``target`` (model units) and every other
        body follows by least change (OndselSolver's drag weights, docs/python.md). Starts from
        ``pose`` (a previous step's :attr:`Dragged.pose`) or, without one, from the drawn pose
        assembled at ``time``. Joint limits hold: a step into a stop ends at the stop
        (:attr:`Dragged.stop` names the limit). Raises :class:`AnalysisError` for an unknown
        body or point, or a pose that cannot be solved."""
        out = _cardan.drag(
            self.text,
            self.path,
            body,
            [float(x) for x in target],
            point,
            None if pose is None else {k: (list(r), list(p)) for k, (r, p) in pose.items()},
            float(time),
            self._native,
        )
        if out["error"] is not None:
            raise_error(out["error"])
        return Dragged(
            pose={k: (tuple(r), tuple(p)) for k, (r, p) in out["pose"].items()},
            reached=out["reached"],
            stop=out["stop"],
            distance=out["distance"],
        )

    def __reduce__(self) -> Any:
        return (Model._trusted, (self.text, self.path))

    def __repr__(self) -> str:
        return f"<cardan.Model {self.path}>"


def load(
    path: "os.PathLike[str] | str",
    units: "str | None" = None,
    *,
    base: "str | None" = None,
    mimic: "str | None" = None,
    limits: "bool | None" = None,
    damping: "bool | None" = None,
    friction: "bool | None" = None,
) -> Model:
    """Reads a model file: TOML, an ASMT assembly (``.asmt``, OndselSolver / FreeCAD) or a URDF
    robot (``.urdf``), imported as cardan does for ``cardan run model.asmt``. ``units`` is for
    ASMT files, as ``--units`` of the command: ``"si"`` (default) or ``"mm"`` (FreeCAD's
    millimetres: the model says ``[model] units = "mm"`` and its results are in mm). A TOML model
    gives its units in ``[model] units``, and ``units=`` is refused for it. ``base``
    (``"fixed"`` or ``"floating"``), ``mimic`` (``"couple"`` or ``"free"``), ``limits`` and
    ``damping``, ``friction`` are for URDF files, as ``--base``, ``--mimic``, ``--no-limits``,
    ``--damping`` and ``--friction``. The import's warnings
    (elements read but ignored) are issued as Python warnings."""
    path = os.path.abspath(os.fspath(path))
    # An unreadable file raises OSError here, whatever its kind (the imports read it in Rust).
    open(path, "rb").close()
    is_urdf = path.lower().endswith(".urdf")
    if not is_urdf and any(v is not None for v in (base, mimic, limits, damping, friction)):
        raise ValueError(f"base=, mimic=, limits=, damping= and friction= apply to URDF files; {path} is not one")
    if is_urdf:
        if units is not None:
            raise ValueError(f"units={units!r} applies to ASMT files; a URDF is in SI units")
        out = _cardan.import_urdf(
            None,
            path,
            base or "fixed",
            mimic or "couple",
            True if limits is None else limits,
            bool(damping),
            bool(friction),
        )
        return _imported(out)
    if path.lower().endswith(".asmt"):
        out = _cardan.import_asmt(None, path, units or "si")
        return _imported(out)
    if units is not None:
        raise ValueError(
            f"units={units!r} applies to ASMT files; {path} gives its units in [model] units"
        )
    with open(path, encoding="utf-8") as f:
        text = f.read()
    return Model(text, path)


def _imported(out: Dict[str, Any]) -> Model:
    """The model of an import (``_cardan.import_asmt``, ``import_urdf``), its warnings issued
    as Python warnings at the caller of :func:`load`; raises the import's error."""
    if out["error"] is not None:
        raise_error(out["error"])
    import warnings

    for w in out["warnings"]:
        warnings.warn(w, stacklevel=3)
    return Model._trusted(out["text"], out["path"], _prepared(out["prepared"]))


# ---------------------------------------------------------------------------------------------
# The builder: a model from Python values, written as model-file text.


def _toml_value(v: Any) -> str:
    """A TOML value of a Python or numpy value."""
    if hasattr(v, "tolist"):  # numpy arrays and scalars
        v = v.tolist()
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if v != v:
            return "nan"
        if v in (float("inf"), float("-inf")):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        import json

        return json.dumps(v)
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_toml_key(k)} = {_toml_value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(f"{type(v).__name__} cannot be written to a model file: give numbers, strings, lists or dicts")


def _toml_key(k: str) -> str:
    import json

    return k if k.replace("_", "").replace("-", "").isalnum() and k.isascii() else json.dumps(k)


@dataclass
class Builder:
    """Builds a model from Python values, mirroring the model file's tables (and so the Rust
    ``MechanismBuilder``): every method takes the keys of its table in
    ``docs/model-format.md`` as keyword arguments, with floats, lists, dicts or numpy arrays.

    >>> b = Builder("pendulum", gravity=[0, 0, -9.81])
    >>> b.ground(points={"O": [0, 0, 0]}, vectors={"x": [1, 0, 0]})
    >>> b.body("rod", mass=1.0, inertia={"diag": [0.1, 0.1, 0.01]}, position=[0, 0, -0.5],
    ...        points={"O": [0, 0, 0.5]}, vectors={"x": [1, 0, 0]})
    >>> b.joint("pin", "revolute", body_i="ground", point_i="O", axis_i="x",
    ...         body_j="rod", point_j="O", axis_j="x")
    >>> b.analysis("dynamic", t_end=1.0, output_dt=0.01)
    >>> model = b.build()

    :meth:`build` validates the model (a bad one raises :class:`ModelError` there); its
    errors name the element, and the line of :meth:`to_toml`'s text."""

    name: str
    gravity: Any = None
    description: Optional[str] = None
    _ground: Dict[str, Any] = field(default_factory=dict)
    _tables: List[tuple] = field(default_factory=list)
    _analysis: Optional[Dict[str, Any]] = None
    _parameters: Dict[str, Any] = field(default_factory=dict)

    def ground(self, **keys: Any) -> "Builder":
        """The ground's points and vectors: ``points={"A": [x, y, z]}``, ``vectors={...}``."""
        self._ground.update(keys)
        return self

    def body(self, name: str, **keys: Any) -> "Builder":
        """A body: ``mass``, ``inertia``, ``position``, ``orientation``, ``points``,
        ``global_points``, ``vectors``, ..."""
        self._tables.append(("body", {"name": name, **keys}))
        return self

    def joint(self, name: str, type: str, **keys: Any) -> "Builder":
        """A joint of a kind (``"revolute"``, ``"spherical"``, ...) between ``body_i`` and
        ``body_j`` at their points and axes."""
        self._tables.append(("joint", {"name": name, "type": type, **keys}))
        return self

    def driver(self, name: str, **keys: Any) -> "Builder":
        """A driver: ``joint``, ``function`` (see :func:`polynomial`, :func:`harmonic`,
        :func:`expression`), ..."""
        self._tables.append(("driver", {"name": name, **keys}))
        return self

    def force(self, name: str, type: str, **keys: Any) -> "Builder":
        """A force element (spring, damper, point force, torque, ...)."""
        self._tables.append(("force", {"name": name, "type": type, **keys}))
        return self

    def curve(self, name: str, type: str, **keys: Any) -> "Builder":
        """A point held on a curve (a slot, a track, a path): ``type`` is ``"line"``,
        ``"circle"``, ``"helix"`` or ``"spline"``; ``body_i`` carries the curve (``point_i``,
        ``axis_i``, ``x_axis_i``, ``radius``, ``pitch``, or a spline's ``points`` in its
        coordinates and ``closed``), ``point_j`` of ``body_j`` follows it. Its parameter u is an
        unknown; a driver of ``type="path"`` with ``curve=name`` prescribes it."""
        self._tables.append(("curve", {"name": name, "type": type, **keys}))
        return self

    def cam(self, name: str, follower: str, **keys: Any) -> "Builder":
        """A cam pair: a follower's curve on ``body_j`` (``follower="flat"``: the line through
        ``point_j`` along ``axis_j``; ``"roller"``: a circle of ``roller_radius``) kept tangent
        to a cam profile on ``body_i`` in the plane normal to ``axis_i`` (``profile="disc"``
        with ``point_i`` and ``radius``, or ``"spline"`` with ``points``). Its parameters u
        (profile) and w (follower) are unknowns, in the joint tables as ``name.u``, ``name.w``."""
        self._tables.append(("cam", {"name": name, "follower": follower, **keys}))
        return self

    def surface(self, name: str, type: str, **keys: Any) -> "Builder":
        """A point held on a surface: ``type`` is ``"plane"``, ``"sphere"``, ``"cylinder"``,
        ``"torus"`` (``point_i``, ``axis_i``, ``x_axis_i``, ``radius``, ``tube_radius``) or
        ``"patch"`` (16 control ``points``) on ``body_i``; ``point_j`` of ``body_j`` stays on it.
        Its parameters u and v are unknowns, in the joint tables as ``name.u``, ``name.v``."""
        self._tables.append(("surface", {"name": name, "type": type, **keys}))
        return self

    def material(self, name: str, **keys: Any) -> "Builder":
        """A contact material: ``stiffness`` (N/m^1.5, with ``exponent``) or
        ``youngs_modulus`` and ``poisson_ratio``, ``restitution``, ``friction``,
        ``friction_static``, ``slip_velocity``; ``between=["a", "b"]`` makes it the law of the
        contacts between materials a and b instead of their combination."""
        self._tables.append(("material", {"name": name, **keys}))
        return self

    def shape(self, name: str, type: str, body: str, material: str, **keys: Any) -> "Builder":
        """A collision shape on ``body`` (``"ground"`` allowed) made of ``material``: ``type`` is
        ``"sphere"``, ``"capsule"``, ``"cylinder"`` (``radius``, ``length``), ``"box"``
        (``size``), ``"plane"``, ``"convex_mesh"`` (``file`` or ``points``) or ``"mesh"`` (a
        ground ``file``); placed at the body's ``point`` with its z along ``axis``."""
        self._tables.append(("shape", {"name": name, "type": type, "body": body, "material": material, **keys}))
        return self

    def coupler(self, name: str, type: str, **keys: Any) -> "Builder":
        """A coupler (gear, rack and pinion, screw) between joint coordinates."""
        self._tables.append(("coupler", {"name": name, "type": type, **keys}))
        return self

    def limit(self, name: str, joint: str, **keys: Any) -> "Builder":
        """End stops on a joint coordinate: ``lower``, ``upper`` (rad or m), ``restitution``,
        or ``law="compliant"`` with ``stiffness``, ``damping``, ``exponent``; ``coordinate``
        names the coordinate of a joint with several."""
        self._tables.append(("limit", {"name": name, "joint": joint, **keys}))
        return self

    def friction(self, name: str, joint: str, coefficient: float | None = None, **keys: Any) -> "Builder":
        """Friction in a joint. With ``coefficient``: Coulomb friction from its reaction, μ =
        ``coefficient``, ``radius`` of a rotating joint, ``preload``, ``stiction_velocity``.
        Without: the ``constant`` law, a slide's ``force`` or a pin's ``torque`` independent of
        the load (``b.friction("f", "slide", force=1.5)``)."""
        table: dict[str, Any] = {"name": name, "joint": joint}
        if coefficient is None:
            table["law"] = "constant"
        else:
            table["coefficient"] = coefficient
        self._tables.append(("friction", {**table, **keys}))
        return self

    def parameters(self, **values: Any) -> "Builder":
        """The ``[parameters]`` table: ``b.parameters(crank="80 mm", speed=2.0)``; any number
        of a table may then be a string using them (``position=["crank", 0, 0]``)."""
        self._parameters.update(values)
        return self

    def analysis(self, kind: str, **keys: Any) -> "Builder":
        """The ``[analysis]`` table: ``t_end``, ``steps``, ``outputs``, ..."""
        self._analysis = {"kind": kind, **keys}
        return self

    def to_toml(self) -> str:
        """The model file text."""
        lines = ["[model]", f"name = {_toml_value(self.name)}"]
        if self.description is not None:
            lines.append(f"description = {_toml_value(self.description)}")
        if self.gravity is not None:
            lines.append(f"gravity = {_toml_value(self.gravity)}")
        if self._parameters:
            lines += ["", "[parameters]"] + [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in self._parameters.items()]
        if self._ground:
            lines += ["", "[ground]"] + [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in self._ground.items()]
        for table, keys in self._tables:
            lines += ["", f"[[{table}]]"] + [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in keys.items()]
        if self._analysis is not None:
            lines += ["", "[analysis]"] + [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in self._analysis.items()]
        return "\n".join(lines) + "\n"

    def build(self) -> Model:
        """The model, validated (its path names the builder in messages)."""
        return Model(self.to_toml(), f"<builder {self.name}>")


def polynomial(coefficients: Any) -> Dict[str, Any]:
    """Time function c0 + c1 t + c2 t² + ..."""
    return {"kind": "polynomial", "coefficients": list(coefficients)}


def harmonic(amplitude: float, frequency: float, phase: float = 0.0, offset: float = 0.0) -> Dict[str, Any]:
    """Time function offset + amplitude sin(frequency t + phase) (frequency in rad/s)."""
    return {"kind": "harmonic", "amplitude": amplitude, "frequency": frequency, "phase": phase, "offset": offset}


def constant(value: float) -> Dict[str, Any]:
    """Time function of one value."""
    return {"kind": "constant", "value": value}


def ramp(t0: float, t1: float, f0: float, f1: float) -> Dict[str, Any]:
    """Time function stepping smoothly (C² quintic) from f0 (t ≤ t0) to f1 (t ≥ t1)."""
    return {"kind": "ramp", "t0": t0, "t1": t1, "f0": f0, "f1": f1}


def spline(times: Any, values: Any) -> Dict[str, Any]:
    """Time function: natural cubic spline through the knots (linear beyond them)."""
    return {"kind": "spline", "times": list(times), "values": list(values)}


def expression(text: str) -> Dict[str, Any]:
    """Time function from an expression in t (``"0.5*sin(2*pi*t)"``)."""
    return {"kind": "expression", "text": text}
