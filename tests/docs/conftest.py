"""Fixtures of the docs tests: the tools they run (the release `cardan`, the test venv's Python)
and a working directory per document that looks like a fresh clone to its commands."""

from __future__ import annotations

import os
import pathlib
import shutil
import sys

import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))

from blocks import ROOT  # noqa: E402


@pytest.fixture(scope="session")
def cardan_bin() -> pathlib.Path:
    """The release `cardan` command (scripts/python-env builds it)."""
    path = pathlib.Path(os.environ.get("CARDAN_BIN") or ROOT / "target" / "release" / "cardan")
    if not path.exists():
        pytest.fail(f"no cardan command at {path}: run the docs tests through scripts/test-docs")
    return path


@pytest.fixture(scope="session")
def venv_python() -> pathlib.Path:
    """The Python of target/py-venv, with the package installed (scripts/python-env)."""
    path = ROOT / "target" / "py-venv" / "bin" / "python"
    if not path.exists():
        pytest.fail(f"no {path}: run the docs tests through scripts/test-docs")
    return path


def workdir(tmp: pathlib.Path, cardan_bin: pathlib.Path) -> pathlib.Path:
    """A directory that looks like a fresh clone to a document's commands: a copy of examples/
    (which the commands may change), target/ linked (the wheel, the venv), and bin/cardan."""
    shutil.copytree(ROOT / "examples", tmp / "examples", ignore=shutil.ignore_patterns("__pycache__"))
    (tmp / "target").symlink_to(ROOT / "target")
    (tmp / "bin").mkdir()
    (tmp / "bin" / "cardan").symlink_to(cardan_bin)
    return tmp


def environment(work: pathlib.Path, venv_python: pathlib.Path) -> dict:
    """The environment of a document's commands: `cardan` first on PATH, then the venv."""
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([str(work / "bin"), str(venv_python.parent), env.get("PATH", "")])
    env["MPLBACKEND"] = "Agg"
    env.pop("PYTHONPATH", None)
    return env
