"""Sweeps: serial, process pool and a Dask cluster give the same table; failing cases are rows."""

import math
from pathlib import Path
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pandas as pd
import pytest

import cardan
from sweep_models import peak_slider_force, peak_torque, slider_crank

PARAMS = cardan.grid(crank=[0.06, 0.07, 0.08, 0.09, 0.1], speed=[0.5, 1.0, 1.5, 2.0])
OUTPUTS = {"peak_torque": peak_torque, "peak_slider_force": peak_slider_force}
OPTIONS = {"t_end": 1.0, "steps": 40}


@pytest.fixture(scope="module")
def serial():
    return cardan.sweep_serial(slider_crank, PARAMS, "inverse_dynamics", OUTPUTS, options=OPTIONS)


def test_grid_is_the_cartesian_product():
    assert len(PARAMS) == 20
    assert PARAMS[0] == {"crank": 0.06, "speed": 0.5} and PARAMS[1] == {"crank": 0.06, "speed": 1.0}


def test_serial_sweep_has_a_row_per_case(serial):
    assert isinstance(serial, pd.DataFrame) and len(serial) == 20
    assert (serial["status"] == "ok").all(), serial["error"].tolist()
    # The motor torque grows with the speed (inertia) at a fixed crank length.
    first = serial[serial["crank"] == 0.08].sort_values("speed")["peak_torque"].to_numpy()
    assert np.all(np.diff(first) > 0)


def test_process_pool_equals_serial(serial):
    pooled = cardan.sweep(slider_crank, PARAMS, "inverse_dynamics", OUTPUTS, options=OPTIONS)
    pd.testing.assert_frame_equal(pooled, serial, check_exact=True)


def test_any_executor(serial):
    with ThreadPoolExecutor(2) as ex:
        threaded = cardan.sweep(slider_crank, PARAMS, "inverse_dynamics", OUTPUTS, executor=ex, options=OPTIONS)
    pd.testing.assert_frame_equal(threaded, serial, check_exact=True)


def test_dask_local_cluster_equals_serial(serial):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            on_cluster = cardan.sweep(slider_crank, PARAMS, "inverse_dynamics", OUTPUTS,
                                      client=client, options=OPTIONS)
    pd.testing.assert_frame_equal(on_cluster, serial, check_exact=True)


def test_failing_cases_are_rows():
    params = [{"crank": 0.08, "speed": 1.0}, {"crank": 0.08, "speed": math.nan}, {"crank": "x", "speed": 1.0}]
    rows = cardan.sweep_serial(slider_crank, params, "inverse_dynamics", OUTPUTS, options=OPTIONS, as_frame=False)
    assert [r["status"] for r in rows] == ["ok", "error", "error"]
    assert rows[1]["error"].startswith("ModelError: ") and "motor" in rows[1]["error"]
    assert rows[2]["error"].startswith("TypeError") or rows[2]["error"].startswith("ValueError")
    assert math.isnan(rows[1]["peak_torque"])


def test_full_results_on_request():
    rows = cardan.sweep_serial(slider_crank, PARAMS[:2], "inverse_dynamics", OUTPUTS, options=OPTIONS,
                               keep_results=True, as_frame=False)
    assert isinstance(rows[0]["results"], cardan.Results)


def test_numpy_scalar_parameters_are_numbers_for_make_model():
    # np.linspace gives np.float64: its repr in an f-string was "np.float64(0.06)" under numpy 2,
    # which the example wrote into the model text (every case failed, issue 46).
    params = cardan.grid(crank=np.linspace(0.06, 0.08, 2), speed=np.array([1.0, 2.0], dtype=np.float32))
    assert all(type(v) is float for p in params for v in p.values())
    rows = cardan.sweep_serial(slider_crank, params, "inverse_dynamics", OUTPUTS, options=OPTIONS, as_frame=False)
    assert [r["status"] for r in rows] == ["ok"] * 4, [r["error"] for r in rows]
    # Parameters not made by grid reach make_model as numbers too.
    rows = cardan.sweep_serial(slider_crank, [{"crank": np.float64(0.08), "speed": np.int64(1)}],
                               "inverse_dynamics", OUTPUTS, options=OPTIONS, as_frame=False)
    assert rows[0]["status"] == "ok", rows[0]["error"]


def test_the_error_column_keeps_the_whole_message():
    rows = cardan.sweep_serial(slider_crank, [{"crank": 0.08, "speed": math.nan}], "inverse_dynamics",
                               OUTPUTS, options=OPTIONS, as_frame=False)
    error = rows[0]["error"]
    # The location (file:line:column) and the source excerpt under it.
    assert error.startswith("ModelError: slider_crank(crank=0.08, speed=nan):"), error
    assert "error:" in error and "\n" in error and "^" in error, error


def test_the_command_line_sweep_gives_the_python_sweep_numbers(tmp_path):
    """`cardan sweep` and `cardan.sweep` over the same grid of the parametric slider-crank:
    the same parameters, the same peak torques, to the last bit."""
    import os
    import subprocess

    from sweep_models import parametric

    cli = os.environ.get("CARDAN_BIN", "cardan")
    model = str(Path(__file__).resolve().parents[3] / "examples" / "slider_crank_parametric.toml")
    subprocess.run(
        [cli, "sweep", model, "--set", "crank=0.06:0.1:3", "--set", "speed=1,4",
         "--output", "peak=max(abs(motor.torque))", "-o", str(tmp_path / "sw")],
        check=True, capture_output=True,
    )
    rows = (tmp_path / "sw" / "sweep.csv").read_text().splitlines()[1:]
    cli_rows = [tuple(float(x) for x in r.split(",")[:3]) for r in rows]
    params = cardan.grid(crank=[0.06, 0.08, 0.1], speed=[1.0, 4.0])
    table = cardan.sweep_serial(parametric, params, outputs={"peak": peak_torque}, as_frame=False)
    py_rows = [(r["crank"], r["speed"], r["peak"]) for r in table]
    assert cli_rows == py_rows
