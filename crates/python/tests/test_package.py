"""Pickling, the type stub, Ctrl-C, the prepared model a Model keeps."""

import concurrent.futures
import inspect
import multiprocessing
import os
import pathlib
import pickle
import signal
import threading

import numpy as np
import pytest

import cardan
from cardan import _cardan
from conftest import EXAMPLES


def test_models_and_results_pickle():
    m = cardan.load(EXAMPLES / "slider_crank_inverse.toml")
    m2 = pickle.loads(pickle.dumps(m))
    assert (m2.text, m2.path) == (m.text, m.path)
    r = m.inverse_dynamics(steps=20)
    r2 = pickle.loads(pickle.dumps(r))
    assert r2.tables.keys() == r.tables.keys() and r2.run == r.run
    for name, t in r.tables.items():
        np.testing.assert_array_equal(r2[name].values, t.values)
        assert r2[name].to_csv() == t.to_csv()


def test_a_model_whose_text_is_replaced_runs_the_new_text():
    # A Model keeps its text prepared for its runs; a text replaced afterwards is prepared
    # afresh (the kept one would give the old text's results).
    m = cardan.load(EXAMPLES / "slider_crank.toml")
    assert len(m.run().points) == 201
    m.text = m.text.replace("steps = 200", "steps = 20")
    assert len(m.run().points) == 21
    assert m.check().dof == 1
    # A model unpickled (without the prepared text) and an imported one run as the original.
    asmt = EXAMPLES.parent / "crates" / "asmt" / "tests" / "data" / "piston.asmt"
    a = cardan.load(asmt)
    a2 = pickle.loads(pickle.dumps(a))
    np.testing.assert_array_equal(a.run().bodies.values, a2.run().bodies.values)


def _rows_of_a_short_run(model):
    return len(model.run(steps=5).points)


def test_a_forked_process_runs_after_its_parent_ran():
    # A run leaves its thread waiting for the next one; a forked child has no such thread and
    # must start its own (handing it the parent's would wait forever).
    m = cardan.load(EXAMPLES / "slider_crank.toml")
    assert _rows_of_a_short_run(m) == 6
    with multiprocessing.get_context("fork").Pool(1) as pool:
        assert pool.apply_async(_rows_of_a_short_run, (m,)).get(timeout=60) == 6


def test_runs_from_several_threads_each_get_their_own_results():
    # Eight runs of different lengths from four Python threads at once, on the kept threads:
    # each caller gets its own run's results (a result handed to the wrong caller has the
    # wrong length).
    m = cardan.load(EXAMPLES / "slider_crank.toml")
    steps = list(range(2, 10))
    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        rows = list(pool.map(lambda n: len(m.run(steps=n).points), steps))
    assert rows == [n + 1 for n in steps]


def test_an_unreadable_file_raises_oserror_whatever_its_kind(tmp_path):
    for name in ("missing.toml", "missing.asmt", "missing.urdf"):
        with pytest.raises(FileNotFoundError):
            cardan.load(tmp_path / name)


def test_the_stub_matches_the_native_module():
    stub = pathlib.Path(cardan.__file__).with_name("_cardan.pyi").read_text()
    public = sorted(n for n in dir(_cardan) if not n.startswith("_") or n == "__version__")
    for name in public:
        obj = getattr(_cardan, name)
        if isinstance(obj, type):
            assert f"class {name}:" in stub, name
            continue
        assert f"def {name}(" in stub or f"{name}:" in stub, name
        if callable(obj):
            params = list(inspect.signature(obj).parameters)
            line = next(l for l in stub.split("def ")[1:] if l.startswith(f"{name}("))
            for p in params:
                assert f"{p}:" in line, (name, p)
    assert (pathlib.Path(cardan.__file__).parent / "py.typed").exists()


def test_ctrl_c_stops_a_run_and_keeps_its_results():
    m = cardan.load(EXAMPLES / "slider_crank.toml")
    # Python raises KeyboardInterrupt on SIGINT only with its default handler, which it does
    # not install when started with SIGINT ignored (a job started in the background by a
    # non-interactive shell, as CI scripts may be): install it, as an interactive session has it.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    # Ctrl-C after 0.5 s, pressed again every 0.5 s while the run goes on (a user does that too;
    # once, a single press was not seen in a CI run and the run went on to its end).
    started = threading.Event()
    finished = threading.Event()

    def press():
        started.wait()
        while not finished.wait(0.5):
            os.kill(os.getpid(), signal.SIGINT)

    presser = threading.Thread(target=press, daemon=True)
    presser.start()
    try:
        with pytest.raises(KeyboardInterrupt) as e:
            started.set()
            m.kinematics(t_end=1000.0, steps=1_000_000, outputs={"points": ["slider.C"]})
    finally:
        finished.set()
        presser.join()
        signal.signal(signal.SIGINT, previous)
    partial = e.value.partial
    assert partial is not None and partial.status == "partial"
    assert 0 < len(partial.t) < 1_000_001
    # The next run is not stopped by the old request.
    assert m.kinematics(steps=10).status == "complete"


def test_the_gil_is_released_during_a_run():
    m = cardan.load(EXAMPLES / "slider_crank.toml")
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            stop.wait(0.001)

    t = threading.Thread(target=count)
    t.start()
    m.kinematics(t_end=20.0, steps=200_000)
    stop.set()
    t.join()
    assert len(ticks) > 20
