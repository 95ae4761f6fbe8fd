"""Every bundled example runs (issue 46): TOML models with `cardan run`, ASMT assemblies and URDF
robots with `cardan run`, `check` and `import` (the imported model checked too), Python examples
with the test venv's Python. An example the documents already run (test_docs.py) is not run again."""

from __future__ import annotations

import subprocess

import pytest

import shell
from blocks import ROOT, blocks, documents
from conftest import environment, workdir

EXAMPLES = sorted(
    p.relative_to(ROOT).as_posix()
    for p in (ROOT / "examples").rglob("*")
    if p.suffix in (".toml", ".asmt", ".urdf", ".py") and "__pycache__" not in p.parts
)


def run_by_docs() -> set:
    """The examples a runnable shell block of the documents runs."""
    found = set()
    for doc in documents():
        for b in blocks(doc):
            if b.lang == "sh" and "no-run" not in b.attrs:
                found.update(shell.examples_run(b.text))
    return found


DOCS_RUN = run_by_docs()


def test_there_are_examples_of_each_kind():
    assert {pathlib_suffix(e) for e in EXAMPLES} == {".toml", ".asmt", ".urdf", ".py"}


def pathlib_suffix(name: str) -> str:
    return name[name.rfind("."):]


@pytest.mark.parametrize("example", EXAMPLES)
def test_example_runs(example, tmp_path, cardan_bin, venv_python):
    imported = example.endswith((".asmt", ".urdf"))
    if example in DOCS_RUN and not imported:
        pytest.skip("run by the documents' blocks (test_docs.py)")
    work = workdir(tmp_path, cardan_bin)
    env = environment(work, venv_python)

    def run(*args: str) -> None:
        out = subprocess.run(list(args), cwd=work, env=env, capture_output=True, text=True, check=False)
        assert out.returncode == 0, f"{' '.join(args)}: exit {out.returncode}\n{out.stdout}{out.stderr}"

    if example.endswith(".py"):
        run(str(venv_python), example, "--out", "out")
    else:
        run("cardan", "run", example, "-o", "out", "--quiet")
    if imported:
        run("cardan", "check", example)
        run("cardan", "import", example, "-o", "imported.toml")
        run("cardan", "check", "imported.toml")
