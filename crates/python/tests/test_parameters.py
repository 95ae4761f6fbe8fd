"""Parameters in Python (issue 52): ``Model.with_parameters`` gives the same numbers as
``cardan run --set``; ``Model.parameters()`` lists the values; the builder writes a
``[parameters]`` table whose names any number may use; mistakes are ModelErrors."""

import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import cardan
from conftest import EXAMPLES

PARAMETRIC = EXAMPLES / "slider_crank_parametric.toml"


def test_parameters_are_listed_with_their_units() -> None:
    p = cardan.load(PARAMETRIC).parameters()
    assert p["crank"].value == pytest.approx(0.08) and p["crank"].unit == "m"
    assert p["speed"].value == pytest.approx(2 * math.pi) and p["speed"].written == "60 rpm"
    assert p["x_c"].in_model == pytest.approx(0.2)


def test_with_parameters_matches_the_command_line(tmp_path: Path) -> None:
    model = cardan.load(PARAMETRIC)
    changed = model.with_parameters(crank=0.06, speed="120 rpm")
    assert changed.parameters()["crank"].value == pytest.approx(0.06)
    # The original is unchanged (models are immutable).
    assert model.parameters()["crank"].value == pytest.approx(0.08)
    torque = changed.run().driver_efforts
    cli = os.environ.get("CARDAN_BIN", "cardan")
    out = tmp_path / "out"
    subprocess.run(
        [cli, "run", str(PARAMETRIC), "-o", str(out), "--quiet", "--set", "crank=0.06", "--set", "speed=120 rpm", "--outputs", "csv"],
        check=True,
    )
    data = np.loadtxt(out / "driver_efforts.csv", delimiter=",", skiprows=1)
    assert np.allclose(torque.values[:, 0], data[:, 1], rtol=0, atol=1e-12)


def test_with_parameters_mistakes_are_model_errors() -> None:
    model = cardan.load(PARAMETRIC)
    with pytest.raises(cardan.ModelError, match='did you mean "crank"'):
        model.with_parameters(crnak=0.1)
    with pytest.raises(cardan.ModelError, match="the value given is in s"):
        model.with_parameters(crank="2 s")
    with pytest.raises(TypeError, match="number or a string"):
        model.with_parameters(crank=[1, 2])


def test_the_builder_writes_parameters_any_number_may_use() -> None:
    b = cardan.Builder("pendulum", gravity=[0, 0, -9.81])
    b.parameters(length="0.5 m", m=2.0)
    b.ground(points={"O": [0, 0, 0]}, vectors={"x": [1, 0, 0]})
    b.body("rod", mass="m", inertia={"diag": [0.1, 0.1, 0.01]}, position=[0, 0, "-length"],
           points={"O": [0, 0, "length"]}, vectors={"x": [1, 0, 0]})
    b.joint("pin", "revolute", body_i="ground", point_i="O", axis_i="x", body_j="rod", point_j="O", axis_j="x")
    b.analysis("dynamic", t_end=0.1, output_dt=0.01)
    model = b.build()
    assert "[parameters]" in model.text
    longer = model.with_parameters(length=1.0)
    assert longer.parameters()["length"].value == 1.0
    assert model.check().dof == 1 and longer.check().dof == 1
