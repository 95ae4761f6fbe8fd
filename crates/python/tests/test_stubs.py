"""The type stubs (cardan/__init__.pyi, _cardan.pyi) match the package, checked by mypy's
stubtest, and a user's script type-checks against them (issue 46: editors complete Model,
Results and the builder)."""

import os
import pathlib
import subprocess
import sys

import pytest

PACKAGE = pathlib.Path(__file__).resolve().parents[1]

USER_SCRIPT = '''
import numpy as np
import numpy.typing as npt
import cardan

model: cardan.Model = cardan.load("examples/slider_crank_inverse.toml")
r: cardan.Results = model.inverse_dynamics(t_end=1.0)
torque: npt.NDArray[np.float64] = r.driver_efforts["motor.torque"]
columns: list[str] = r.points.columns
b = cardan.Builder("p").ground(points={"O": [0, 0, 0]}).body("rod", mass=1.0)
m2: cardan.Model = b.build()
try:
    cardan.Model.from_toml("")
except cardan.ModelError as e:
    where: tuple[str | None, int | None, int | None, str | None] = (e.file, e.line, e.column, e.element)
'''


def mypy(args, tmp_path):
    pytest.importorskip("mypy")
    env = dict(os.environ, MYPY_CACHE_DIR=str(tmp_path / "mypy-cache"))
    return subprocess.run([sys.executable, "-m", *args, "--config-file" if args[0] == "mypy" else "--mypy-config-file",
                           str(PACKAGE / "pyproject.toml")], capture_output=True, text=True, cwd=tmp_path, env=env,
                          check=False)


def test_the_stubs_match_the_package(tmp_path):
    out = mypy(["mypy.stubtest", "cardan"], tmp_path)
    assert out.returncode == 0, out.stdout + out.stderr


def test_a_users_script_type_checks(tmp_path):
    (tmp_path / "user.py").write_text(USER_SCRIPT)
    out = mypy(["mypy", "user.py"], tmp_path)
    assert out.returncode == 0, out.stdout + out.stderr
