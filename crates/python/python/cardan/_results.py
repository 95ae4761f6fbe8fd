"""Results of an analysis as numpy arrays: one :class:`Table` per output file of ``cardan run``."""

from __future__ import annotations

import json
import os
import re
from typing import Any, Dict, Iterator, List, Optional, Tuple

import numpy as np

from . import _cardan

_HEADER = re.compile(r"^(.*?)(?: \[(.*)\])?$")


def split_header(header: str) -> Tuple[str, str]:
    """``"crank.B.x [m]"`` → ``("crank.B.x", "m")``; a header without a unit gives ``""``."""
    m = _HEADER.match(header)
    assert m is not None
    return m.group(1), m.group(2) or ""


class Table:
    """One output group (``points``, ``joints``, ``reactions``, ...), as the CSV file of the
    same name: ``t`` (the times, s) and ``values`` (one row per time, one column per header).

    ``columns`` are the CSV headers (``"crank.B.x [m]"``), ``names`` the same without units,
    ``units`` the units. ``table["crank.B.x"]`` (or the full header) is one column."""

    def __init__(self, name: str, title: str, columns: List[str], data: np.ndarray) -> None:
        self.name = name
        self.title = title
        self.columns = list(columns)
        self._split: Optional[List[Tuple[str, str]]] = None
        self._data = data
        if data.flags.writeable:
            data.setflags(write=False)

    @classmethod
    def _from_native(cls, name: str, title: str, columns: List[str], raw: bytes, rows: int) -> "Table":
        # A read-only view of the bytes the extension made: no copy.
        data = np.frombuffer(raw, dtype="<f8").reshape(rows, len(columns) + 1)
        return cls(name, title, columns, data)

    @property
    def names(self) -> List[str]:
        """The headers without their units (``"crank.B.x"``)."""
        return [s[0] for s in self._headers()]

    @property
    def units(self) -> List[str]:
        """The headers' units (``"m"``; ``""`` for a header without one)."""
        return [s[1] for s in self._headers()]

    def _headers(self) -> List[Tuple[str, str]]:
        # Split when first asked for: a run makes many tables that are never read by name.
        if self._split is None:
            self._split = [split_header(c) for c in self.columns]
        return self._split

    @property
    def t(self) -> np.ndarray:
        """The output times [s]."""
        return self._data[:, 0]

    @property
    def values(self) -> np.ndarray:
        """The values: ``values[k, c]`` is column ``c`` at ``t[k]`` (float64, read-only)."""
        return self._data[:, 1:]

    def __len__(self) -> int:
        return self._data.shape[0]

    def __getitem__(self, column: str) -> np.ndarray:
        for k, (full, (short, _)) in enumerate(zip(self.columns, self._headers())):
            if column in (full, short):
                return self._data[:, k + 1]
        raise KeyError(f"{self.name} has no column {column!r}; its columns are {', '.join(self.names)}")

    def __contains__(self, column: object) -> bool:
        return column in self.columns or column in self.names

    def unit(self, column: str) -> str:
        """The unit of a column (by name or full header)."""
        for full, (short, unit) in zip(self.columns, self._headers()):
            if column in (full, short):
                return unit
        raise KeyError(column)

    def to_csv(self) -> str:
        """The CSV text, exactly as ``cardan run`` writes ``<name>.csv``."""
        return _cardan.table_csv(self.name, self.title, self.columns, self._data.astype("<f8").tobytes())

    def to_pandas(self) -> Any:
        """A pandas DataFrame indexed by ``t [s]``, one column per header (needs pandas)."""
        import pandas as pd

        index = pd.Index(self.t, name="t [s]")
        return pd.DataFrame(self.values, index=index, columns=self.columns)

    def __repr__(self) -> str:
        return f"<cardan.Table {self.name}: {len(self)} times × {len(self.columns)} columns>"

    def __reduce__(self) -> Any:
        return (Table, (self.name, self.title, self.columns, np.array(self._data)))


class Contacts:
    """``contacts.csv`` of a run with collision shapes, one row per contact point and output
    time: ``t`` (s), ``shape_1``, ``body_1``, ``shape_2``, ``body_2`` (lists of names) and the
    numeric columns by name (``contacts["normal_force"]``, ``contacts["point.x"]``: float64
    arrays), their units in ``units``. ``between(a, b)`` selects the rows of two shapes (either
    order). An output time with no contact has no row."""

    def __init__(self, text: str) -> None:
        import csv
        import io

        rows = list(csv.reader(io.StringIO(text)))
        header, body = rows[0], rows[1:]
        split = [split_header(h) for h in header]
        self.names = [s[0] for s in split]
        self.units = {s[0]: s[1] for s in split}
        text_cols = {"shape_1", "body_1", "shape_2", "body_2"}
        self._text = {n: [r[k] for r in body] for k, n in enumerate(self.names) if n in text_cols}
        self._num = {
            n: np.array([float(r[k]) for r in body], dtype=np.float64)
            for k, n in enumerate(self.names) if n not in text_cols
        }
        self.t = self._num.pop("t")
        self.shape_1, self.body_1 = self._text["shape_1"], self._text["body_1"]
        self.shape_2, self.body_2 = self._text["shape_2"], self._text["body_2"]

    def __len__(self) -> int:
        return len(self.t)

    def __getitem__(self, column: str) -> np.ndarray:
        try:
            return self._num[column]
        except KeyError:
            raise KeyError(f"contacts has no numeric column {column!r}; its columns are {', '.join(self._num)}") from None

    @property
    def columns(self) -> List[str]:
        """The numeric columns' names."""
        return list(self._num)

    def between(self, a: str, b: str) -> np.ndarray:
        """A boolean mask of the rows where shapes ``a`` and ``b`` touch."""
        return np.array([{s1, s2} == {a, b} for s1, s2 in zip(self.shape_1, self.shape_2)], dtype=bool)

    def to_pandas(self) -> Any:
        """A pandas DataFrame with every column (needs pandas)."""
        import pandas as pd

        data: Dict[str, Any] = {"t": self.t, **self._text, **self._num}
        return pd.DataFrame(data)

    def __repr__(self) -> str:
        return f"<cardan.Contacts: {len(self)} contact points>"


class JointSpace:
    """The joint space of an inverse dynamics run (``[analysis.outputs] joint_space = true``
    and ``jacobians``), as arrays in the coordinates the drivers prescribe, in their order:

    - ``coordinates``: the drivers' names (n);
    - ``t``: the output times (T);
    - ``M``: the mass matrix M(θ), shape (T, n, n);
    - ``h``: the bias forces h(θ, θ̇) (the efforts at θ̈ = 0), shape (T, n), so that the
      drivers' efforts are ``M @ θ̈ + h``;
    - ``jacobians``: ``"body.point"`` → shape (T, 6, n): rows ẋ ẏ ż of the point and ω_x ω_y
      ω_z of its body per unit rate of each coordinate, global axes (Pinocchio's
      ``LOCAL_WORLD_ALIGNED``)."""

    def __init__(self, coordinates: List[str], t: np.ndarray, M: np.ndarray, h: np.ndarray,
                 jacobians: Dict[str, np.ndarray]) -> None:
        self.coordinates = coordinates
        self.t = t
        self.M = M
        self.h = h
        self.jacobians = jacobians

    @classmethod
    def _from_tables(cls, mass: Table, bias: Table, jac: Optional[Table]) -> "JointSpace":
        coordinates = [name.rsplit(".", 1)[0] for name in bias.names]
        n, count = len(coordinates), len(bias)
        M = np.array(mass.values).reshape(count, n, n)
        h = np.array(bias.values)
        jacobians: Dict[str, np.ndarray] = {}
        if jac is not None:
            block = 6 * n
            for p in range(len(jac.names) // block):
                # "body.point.vx.<coordinate>": the point is what precedes the row's name.
                point = jac.names[p * block][: -len(f".vx.{coordinates[0]}")]
                jacobians[point] = np.array(jac.values[:, p * block:(p + 1) * block]).reshape(count, 6, n)
        return cls(coordinates, np.array(bias.t), M, h, jacobians)

    def __repr__(self) -> str:
        return (f"<cardan.JointSpace: {len(self.coordinates)} coordinates, {len(self.t)} times, "
                f"{len(self.jacobians)} Jacobians>")


class Results:
    """What an analysis computed: its :class:`Table` s by name (``results.points``,
    ``results["reactions"]``), the run summary (``run``: the contents of ``run.json``) and its
    ``warnings`` (doubtful results: read them).

    ``status`` is ``"complete"``, or ``"partial"`` for the results of a run that failed or was
    stopped (attached to the exception)."""

    def __init__(
        self,
        kind: str,
        tables: Dict[str, Table],
        run: Dict[str, Any],
        native_seconds: float = 0.0,
        glb: Optional[bytes] = None,
        html: Optional[str] = None,
        files: Optional[Dict[str, str]] = None,
    ) -> None:
        self.kind = kind
        self.tables = tables
        self.run = run
        #: Wall time of the Rust side of the run (reading, building, analysing) [s].
        self.native_seconds = native_seconds
        #: The 3D animation (glTF binary) of a run with ``report=True``.
        self.glb = glb
        #: The report page (one self-contained HTML file) of a run with ``report=True``.
        self.html = html
        #: Other output files by name (a modal run's MatrixMarket matrices), as text.
        self.files = dict(files or {})

    # The tables, by the name of their CSV file (docs/model-format.md, "Output files"): editors
    # complete them; a run without one raises AttributeError naming the tables it has.
    @property
    def points(self) -> Table:
        """``points.csv``: positions of the named points."""
        return self._table("points")

    @property
    def point_velocities(self) -> Table:
        """``point_velocities.csv``: velocities of the named points."""
        return self._table("point_velocities")

    @property
    def point_accelerations(self) -> Table:
        """``point_accelerations.csv``: accelerations of the named points."""
        return self._table("point_accelerations")

    @property
    def joints(self) -> Table:
        """``joints.csv``: joint coordinates (angles, slides)."""
        return self._table("joints")

    @property
    def joint_velocities(self) -> Table:
        """``joint_velocities.csv``: rates of the joint coordinates."""
        return self._table("joint_velocities")

    @property
    def joint_accelerations(self) -> Table:
        """``joint_accelerations.csv``: second derivatives of the joint coordinates."""
        return self._table("joint_accelerations")

    @property
    def bodies(self) -> Table:
        """``bodies.csv``: body positions and Euler parameters."""
        return self._table("bodies")

    @property
    def body_velocities(self) -> Table:
        """``body_velocities.csv``: body velocities and angular velocities."""
        return self._table("body_velocities")

    @property
    def body_accelerations(self) -> Table:
        """``body_accelerations.csv``: body accelerations and angular accelerations."""
        return self._table("body_accelerations")

    @property
    def reactions(self) -> Table:
        """``reactions.csv``: joint reaction forces and torques, global axes."""
        return self._table("reactions")

    @property
    def reactions_local(self) -> Table:
        """``reactions_local.csv``: joint reaction forces and torques, body axes."""
        return self._table("reactions_local")

    @property
    def driver_efforts(self) -> Table:
        """``driver_efforts.csv``: motor torques and forces of the drivers."""
        return self._table("driver_efforts")

    @property
    def coupler_efforts(self) -> Table:
        """``coupler_efforts.csv``: forces of the couplers (gears, screws, racks)."""
        return self._table("coupler_efforts")

    @property
    def energy(self) -> Table:
        """``energy.csv``: energies, powers, work and the energy balance."""
        return self._table("energy")

    @property
    def constraint_drift(self) -> Table:
        """``constraint_drift.csv``: largest constraint violation of a dynamic run."""
        return self._table("constraint_drift")

    @property
    def residual(self) -> Table:
        """``residual.csv``: largest Newton residual per output time."""
        return self._table("residual")

    @property
    def stability(self) -> Table:
        """``stability.csv``: stability of static equilibria."""
        return self._table("stability")

    @property
    def modes(self) -> Table:
        """``modes.csv``: natural frequencies and damping ratios."""
        return self._table("modes")

    @property
    def mode_shapes(self) -> Table:
        """``mode_shapes.csv``: mode shapes."""
        return self._table("mode_shapes")

    def contacts(self) -> Contacts:
        """The contact points of a run with collision shapes (``contacts.csv``) as arrays
        (:class:`Contacts`)."""
        if "contacts.csv" not in self.files:
            raise AttributeError("no contacts: the model has no [[shape]]s (docs/model-format.md, contact)")
        return Contacts(self.files["contacts.csv"])

    def joint_space(self) -> JointSpace:
        """The mass matrix, bias forces and Jacobians of an inverse dynamics run as arrays
        (:class:`JointSpace`); the run needs ``[analysis.outputs] joint_space = true``."""
        if "mass_matrix" not in self.tables:
            raise AttributeError(
                "no joint space: run an inverse dynamics analysis with [analysis.outputs] "
                "joint_space = true (and jacobians = [\"body.point\", ...] for Jacobians)"
            )
        return JointSpace._from_tables(self.tables["mass_matrix"], self.tables["bias_forces"],
                                       self.tables.get("jacobians"))

    def _table(self, name: str) -> Table:
        try:
            return self.tables[name]
        except KeyError:
            raise AttributeError(
                f"no table {name!r}; this {self.kind} run has {', '.join(self.tables)}"
            ) from None

    @classmethod
    def _from_native(cls, out: dict) -> "Results":
        tables = {t[0]: Table._from_native(*t) for t in out["tables"]}
        run = json.loads(out["run_json"]) if out["run_json"] else {}
        return cls(out["kind"], tables, run, out.get("seconds", 0.0), out.get("glb"), out.get("html"), dict(out.get("files", [])))

    @property
    def warnings(self) -> List[str]:
        """Doubtful results, one sentence each (as printed by ``cardan run``)."""
        return list(self.run.get("warnings", []))

    @property
    def status(self) -> str:
        """``"complete"`` or ``"partial"``."""
        return str(self.run.get("status", "complete"))

    @property
    def t(self) -> np.ndarray:
        """The output times [s] (those of the first table)."""
        return next(iter(self.tables.values())).t

    def __getitem__(self, name: str) -> Table:
        try:
            return self.tables[name]
        except KeyError:
            raise KeyError(
                f"no table {name!r}; this {self.kind} run has {', '.join(self.tables)}"
            ) from None

    def __getattr__(self, name: str) -> Table:
        if name.startswith("_") or name in ("tables", "kind", "run", "native_seconds", "glb", "html", "files"):
            raise AttributeError(name)
        return self._table(name)

    def __iter__(self) -> Iterator[Table]:
        return iter(self.tables.values())

    def __dir__(self) -> List[str]:
        return list(super().__dir__()) + list(self.tables)

    def to_csv(self, directory: "os.PathLike[str] | str") -> List[str]:
        """Writes ``<name>.csv`` for every table into ``directory`` (created if needed), each
        byte for byte as ``cardan run`` writes it, and ``run.json``; returns the paths."""
        os.makedirs(directory, exist_ok=True)
        paths = []
        for t in self.tables.values():
            path = os.path.join(directory, f"{t.name}.csv")
            with open(path, "w", encoding="utf-8", newline="") as f:
                f.write(t.to_csv())
            paths.append(path)
        for name, text in self.files.items():
            path = os.path.join(directory, name)
            with open(path, "w", encoding="utf-8", newline="") as f:
                f.write(text)
            paths.append(path)
        path = os.path.join(directory, "run.json")
        with open(path, "w", encoding="utf-8") as f:
            json.dump(self.run, f, indent=2)
        paths.append(path)
        return paths

    def save_report(self, directory: "os.PathLike[str] | str") -> List[str]:
        """Writes ``animation.glb`` and ``index.html`` (a run with ``report=True``) into
        ``directory``; returns the paths."""
        if self.glb is None or self.html is None:
            raise ValueError("this run made no report: run it with report=True")
        os.makedirs(directory, exist_ok=True)
        glb, page = os.path.join(directory, "animation.glb"), os.path.join(directory, "index.html")
        with open(glb, "wb") as f:
            f.write(self.glb)
        with open(page, "w", encoding="utf-8") as f:
            f.write(self.html)
        return [glb, page]

    def _repr_html_(self) -> Optional[str]:
        """Jupyter: the report page (3D view, plots, summary) inline, for a run with
        ``report=True``; else the default representation."""
        if self.html is None:
            return None
        import html as html_escape

        doc = html_escape.escape(self.html, quote=True)
        return f'<iframe srcdoc="{doc}" style="width:100%;height:720px;border:0" sandbox="allow-scripts"></iframe>'


    def to_pandas(self, table: Optional[str] = None) -> Any:
        """One table as a DataFrame, or all of them as a dict of DataFrames (needs pandas)."""
        if table is not None:
            return self[table].to_pandas()
        return {name: t.to_pandas() for name, t in self.tables.items()}

    def plot(self, table: str, columns: Optional[List[str]] = None, ax: Any = None) -> Any:
        """Plots columns of a table against time with matplotlib, one axis per unit (units
        never share an axis); returns the figure."""
        import matplotlib.pyplot as plt

        tab = self[table]
        chosen = columns or tab.names
        units: Dict[str, List[str]] = {}
        for c in chosen:
            units.setdefault(tab.unit(c), []).append(c)
        axes: List[Any]
        if ax is not None and len(units) == 1:
            axes = [ax]
            fig = ax.figure
        else:
            fig, grid = plt.subplots(len(units), 1, sharex=True, squeeze=False, figsize=(7, 2.6 * len(units)))
            axes = list(grid[:, 0])
        for a, (unit, cols) in zip(axes, units.items()):
            for c in cols:
                a.plot(tab.t, tab[c], label=c)
            a.set_ylabel(f"[{unit}]" if unit else "")
            a.legend(fontsize="small", loc="best")
            a.grid(True, alpha=0.3)
        axes[-1].set_xlabel("t [s]")
        fig.suptitle(tab.title)
        return fig

    def __repr__(self) -> str:
        return f"<cardan.Results {self.kind} ({self.status}): {len(self.t)} times, tables {', '.join(self.tables)}>"

    def __reduce__(self) -> Any:
        return (Results, (self.kind, self.tables, self.run, self.native_seconds, self.glb, self.html, self.files))
