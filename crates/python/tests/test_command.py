"""`python -m cardan` (and the `cardan` console script) is the `cardan` command: the same
files, summary, messages and exit codes (issue 46)."""

import subprocess
import sys

from conftest import EXAMPLES


def command(args, cwd):
    return subprocess.run([sys.executable, "-m", "cardan", *args], capture_output=True, text=True, cwd=cwd, check=False)


def test_run_writes_what_the_command_writes(cardan_bin, tmp_path):
    model = str(EXAMPLES / "slider_crank.toml")
    py = command(["run", model, "-o", "py", "--quiet"], tmp_path)
    cli = subprocess.run([cardan_bin, "run", model, "-o", "cli", "--quiet"], capture_output=True, text=True,
                         cwd=tmp_path, check=False)
    assert py.returncode == cli.returncode == 0, py.stderr
    files = sorted(p.name for p in (tmp_path / "cli").iterdir())
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == files
    for name in files:
        if name.endswith(".csv") or name.endswith(".svg"):
            assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    # The summary names the same files and the report; only the directory differs.
    assert py.stdout.replace("py", "cli").splitlines()[0] == cli.stdout.splitlines()[0]


def test_errors_and_exit_codes_are_the_commands(cardan_bin, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text((EXAMPLES / "slider_crank.toml").read_text().replace('type = "spherical"', 'type = "sphrical"'))
    py = command(["check", str(bad)], tmp_path)
    cli = subprocess.run([cardan_bin, "check", str(bad)], capture_output=True, text=True, check=False)
    assert py.returncode == cli.returncode == 1
    assert py.stderr == cli.stderr and "sphrical" in py.stderr
    usage = command(["frobnicate"], tmp_path)
    assert usage.returncode == 2 and "python -m cardan" in usage.stderr
