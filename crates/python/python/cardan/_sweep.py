"""Design sweeps: one analysis per parameter set, on a process pool, any
``concurrent.futures.Executor`` or a Dask cluster."""

from __future__ import annotations

import itertools
import os
import traceback
from concurrent.futures import Executor, ProcessPoolExecutor
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Union

import numpy as np

from ._errors import CardanError
from ._model import Model
from ._results import Results

Outputs = Union[Mapping[str, Callable[[Results], Any]], Iterable[Callable[[Results], Any]]]


def plain(value: Any) -> Any:
    """A numpy scalar (``np.float64(0.1)``, ``np.int32(3)``, ``np.bool_``) as the Python
    number it holds; any other value unchanged. Parameters reach ``make_model`` so, and an
    f-string or ``repr`` of them writes ``0.1``, not ``np.float64(0.1)``."""
    return value.item() if isinstance(value, np.generic) else value


def grid(**axes: Iterable[Any]) -> List[Dict[str, Any]]:
    """Every combination of the given values, the last axis varying fastest:
    ``grid(a=[1, 2], b=[10, 20])`` → ``[{a: 1, b: 10}, {a: 1, b: 20}, {a: 2, b: 10}, ...]``.
    Values may be lists or numpy arrays (``np.linspace(...)``); numpy scalars become Python
    numbers."""
    names = list(axes)
    values = [[plain(x) for x in v] for v in axes.values()]
    return [dict(zip(names, combo)) for combo in itertools.product(*values)]


def _named_outputs(outputs: Outputs) -> Dict[str, Callable[[Results], Any]]:
    if isinstance(outputs, Mapping):
        return dict(outputs)
    return {getattr(f, "__name__", f"output_{k}"): f for k, f in enumerate(outputs)}


def _analyse(model: Model, analysis: Union[str, Callable[[Model], Results]], options: Mapping[str, Any]) -> Results:
    if callable(analysis):
        return analysis(model)
    kinds = {
        "kinematic": "kinematic",
        "kinematics": "kinematic",
        "inverse_dynamics": "inverse_dynamics",
        "dynamic": "dynamic",
        "dynamics": "dynamic",
        "file": None,
    }
    if analysis not in kinds:
        raise ValueError(f"analysis {analysis!r}: use one of {', '.join(kinds)} or a function of the model")
    return model.run(kinds[analysis], **options)


def run_case(
    make_model: Callable[..., Model],
    params: Dict[str, Any],
    analysis: Union[str, Callable[[Model], Results]],
    outputs: Dict[str, Callable[[Results], Any]],
    options: Mapping[str, Any],
    keep_results: bool,
) -> Dict[str, Any]:
    """One case of a sweep: a row with the parameters, the outputs, ``status`` (``"ok"`` or
    ``"error"``) and ``error`` (the whole message, with the model's file, line and column and
    the source excerpt; ``""`` when ok); ``results`` too when kept. Numpy scalar parameters
    reach ``make_model`` as Python numbers (:func:`plain`). Never raises for a failing model
    or analysis: the failure is the row."""
    params = {name: plain(value) for name, value in params.items()}
    row: Dict[str, Any] = dict(params)
    try:
        results = _analyse(make_model(**params), analysis, options)
        for name, f in outputs.items():
            row[name] = f(results)
        row["status"], row["error"] = "ok", ""
        if keep_results:
            row["results"] = results
    except CardanError as e:
        for name in outputs:
            row.setdefault(name, float("nan"))
        row["status"], row["error"] = "error", f"{type(e).__name__}: {e.printed}"
    except Exception as e:  # a failing make_model or output function is a row too
        for name in outputs:
            row.setdefault(name, float("nan"))
        last = traceback.extract_tb(e.__traceback__)[-1:]
        where = f" ({last[0].filename}:{last[0].lineno})" if last else ""
        row["status"], row["error"] = "error", f"{type(e).__name__}: {e}{where}"
    return row


def run_cases(
    make_model: Callable[..., Model],
    params: List[Dict[str, Any]],
    analysis: Union[str, Callable[[Model], Results]],
    outputs: Dict[str, Callable[[Results], Any]],
    options: Mapping[str, Any],
    keep_results: bool,
) -> List[Dict[str, Any]]:
    """:func:`run_case` for a chunk of cases (one task of a pool or cluster)."""
    return [run_case(make_model, p, analysis, outputs, options, keep_results) for p in params]


def _workers(executor: Any, client: Any) -> Optional[int]:
    """The number of workers of a pool or cluster, when it can be told."""
    if client is not None:
        try:
            return sum(client.nthreads().values()) or None
        except Exception:
            return None
    n = getattr(executor, "_max_workers", None)
    return n if isinstance(n, int) and n > 0 else None


def sweep(
    make_model: Callable[..., Model],
    params: Iterable[Mapping[str, Any]],
    analysis: Union[str, Callable[[Model], Results]] = "file",
    outputs: Optional[Outputs] = None,
    executor: Optional[Executor] = None,
    client: Any = None,
    options: Optional[Mapping[str, Any]] = None,
    keep_results: bool = False,
    as_frame: Optional[bool] = None,
    chunksize: Optional[int] = None,
) -> Any:
    """Runs ``analysis`` on ``make_model(**p)`` for every parameter set ``p`` of ``params``
    (e.g. :func:`grid`) and keeps the ``outputs``: scalars computed from each case's
    :class:`Results` (a dict name → function, or a list of named functions).

    - ``analysis``: ``"file"`` (the model's own ``[analysis]``), ``"kinematics"``,
      ``"inverse_dynamics"``, ``"dynamics"``, or a function of the model returning Results;
      ``options``: ``[analysis]`` keys set for every case.
    - Where the cases run: ``executor`` (any ``concurrent.futures.Executor``), or ``client``
      (a ``distributed.Client``: the cases run on its cluster), else a local process pool with
      one worker per core. ``make_model`` and the output functions must be picklable
      (module-level functions) for process pools and clusters.
    - Only each case's row travels back unless ``keep_results`` is set (then the row's
      ``results`` holds the full :class:`Results`).
    - Cases travel in chunks of ``chunksize`` (default: about four chunks per worker), so a
      sweep of short analyses is not dominated by the pool's cost per task.

    Returns one row per case in the order of ``params``: its parameters, outputs, ``status``
    (``"ok"``/``"error"``) and ``error`` (the message). A failing case is a row, not an
    exception. A pandas DataFrame when pandas is installed (``as_frame=None``) or asked for,
    else a list of dicts."""
    cases = [dict(p) for p in params]
    named = _named_outputs(outputs or {})
    opts = dict(options or {})
    args = (analysis, named, opts, keep_results)
    own_pool = None
    workers = _workers(executor, client)
    if client is not None:
        executor = client.get_executor()
    if executor is None:
        workers = min(os.cpu_count() or 1, max(len(cases), 1))
        own_pool = ProcessPoolExecutor(max_workers=workers)
        executor = own_pool
    size = chunksize or max(1, -(-len(cases) // (4 * (workers or 8))))
    chunks = [cases[k : k + size] for k in range(0, len(cases), size)]
    try:
        futures = [executor.submit(run_cases, make_model, c, *args) for c in chunks]
        rows = [row for f in futures for row in f.result()]
    finally:
        if own_pool is not None:
            own_pool.shutdown()
    return _frame(rows, as_frame)


def sweep_serial(
    make_model: Callable[..., Model],
    params: Iterable[Mapping[str, Any]],
    analysis: Union[str, Callable[[Model], Results]] = "file",
    outputs: Optional[Outputs] = None,
    options: Optional[Mapping[str, Any]] = None,
    keep_results: bool = False,
    as_frame: Optional[bool] = None,
) -> Any:
    """:func:`sweep` in this process, one case after the other (for debugging a sweep and as
    the reference of a parallel one)."""
    named = _named_outputs(outputs or {})
    rows = [run_case(make_model, dict(p), analysis, named, dict(options or {}), keep_results) for p in params]
    return _frame(rows, as_frame)


def _frame(rows: List[Dict[str, Any]], as_frame: Optional[bool]) -> Any:
    if as_frame is False:
        return rows
    try:
        import pandas as pd
    except ImportError:
        if as_frame:
            raise
        return rows
    return pd.DataFrame(rows)
