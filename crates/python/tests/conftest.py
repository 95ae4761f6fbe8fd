"""Shared fixtures: the repository root, the bundled examples and the `cardan` command."""

import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "examples"
# The Python examples are importable (their model factories are shared with the tests; worker
# processes inherit sys.path).
sys.path.insert(0, str(EXAMPLES / "python"))


@pytest.fixture(scope="session")
def cardan_bin() -> str:
    """The `cardan` command the Python results are compared with (scripts/test-python builds it)."""
    path = os.environ.get("CARDAN_BIN") or str(ROOT / "target" / "release" / "cardan")
    if not os.path.exists(path):
        pytest.fail(f"no cardan command at {path}: run the tests through scripts/test-python")
    return path


def run_cli(cardan_bin: str, model: pathlib.Path, out: pathlib.Path) -> subprocess.CompletedProcess:
    """`cardan run MODEL -o OUT --quiet`."""
    return subprocess.run(
        [cardan_bin, "run", str(model), "-o", str(out), "--quiet"],
        capture_output=True,
        text=True,
        check=False,
    )
